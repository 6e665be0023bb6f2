#include "lrd/features/fast_scores.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>

#include "lrd/util/cpu_features.h"

namespace lrd::features {
namespace {

// The 16 pixels of the radius-3 Bresenham circle in turn (OpenCV's makeOffsets order), (dx, dy).
constexpr int kCircle[16][2] = {{0, 3},  {1, 3},   {2, 2},   {3, 1},   {3, 0},  {3, -1}, {2, -2}, {1, -3},
                                {0, -3}, {-1, -3}, {-2, -2}, {-3, -1}, {-3, 0}, {-3, 1}, {-2, 2}, {-1, 3}};
constexpr int kLanes = 32;

// 32 pixels at a time with GCC's vector extensions: the same code for a scalar and a vector type.
// The helpers taking 32-byte vectors are always inlined and file-local, so the ABI GCC warns about
// for them (passing such vectors without AVX) is never used.
#pragma GCC diagnostic ignored "-Wpsabi"
using Bytes32 = std::uint8_t __attribute__((vector_size(kLanes)));

template <class T>
[[gnu::always_inline]] inline T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}
template <class T>
[[gnu::always_inline]] inline T smaller(T a, T b) {
  return a < b ? a : b;
}
template <class T>
[[gnu::always_inline]] inline T larger(T a, T b) {
  return a > b ? a : b;
}

// max over the 16 arcs of 9 contiguous circle pixels of the arc's minimum contrast.
template <class T>
[[gnu::always_inline]] inline T best_arc(const std::array<T, 16>& c) {
  std::array<T, 16> two, four;
  for (int k = 0; k < 16; ++k) two[k] = smaller(c[k], c[(k + 1) & 15]);
  for (int k = 0; k < 16; ++k) four[k] = smaller(two[k], two[(k + 2) & 15]);
  T best = smaller(smaller(four[0], four[4]), c[8]);
  for (int k = 1; k < 16; ++k)
    best = larger(best, smaller(smaller(four[k], four[(k + 4) & 15]), c[(k + 8) & 15]));
  return best;
}

// The score of the pixel (or the 32 pixels) at `centre`. Contrasts saturate at 0: where an arc is
// brighter (darker) by s > 0, so is its saturated contrast, and a pixel with no such arc scores 0,
// below every threshold, as OpenCV's negative cornerScore.
template <class T>
[[gnu::always_inline]] inline T score_at(const std::uint8_t* centre, const std::ptrdiff_t* offset) {
  const T v = load<T>(centre);
  std::array<T, 16> brighter, darker;
  for (int k = 0; k < 16; ++k) {
    const T p = load<T>(centre + offset[k]);
    const T high = larger(p, v);
    brighter[k] = static_cast<T>(high - v);
    darker[k] = static_cast<T>(high - p);
  }
  return larger(best_arc(brighter), best_arc(darker));
}

// Whether any of the 32 pixels at `centre` can score above `floor`: every arc of 9 holds two
// neighbouring compass points (circle pixels 0, 4, 8, 12), both brighter or both darker by the
// arc's contrast.
[[gnu::always_inline]] inline bool may_score_above(const std::uint8_t* centre, const std::ptrdiff_t* offset,
                                                   Bytes32 floor) {
  const Bytes32 v = load<Bytes32>(centre);
  std::array<Bytes32, 4> brighter, darker;
  for (int k = 0; k < 4; ++k) {
    const Bytes32 p = load<Bytes32>(centre + offset[4 * k]);
    const Bytes32 high = larger(p, v);
    brighter[k] = high - v;
    darker[k] = high - p;
  }
  Bytes32 best = smaller(brighter[3], brighter[0]);
  best = larger(best, smaller(darker[3], darker[0]));
  for (int k = 0; k < 3; ++k)
    best = larger(best, larger(smaller(brighter[k], brighter[k + 1]), smaller(darker[k], darker[k + 1])));
  const Bytes32 above = reinterpret_cast<Bytes32>(best > floor);
  std::uint64_t words[kLanes / 8];
  std::memcpy(words, &above, kLanes);
  return (words[0] | words[1] | words[2] | words[3]) != 0;
}

// One row of `n` pixels from `centre`; the last block overlaps the one before it. Blocks where no
// pixel can score above `floor` read 0.
[[gnu::always_inline]] inline void score_row(const std::uint8_t* centre, const std::ptrdiff_t* offset, int n,
                                             std::uint8_t floor, std::uint8_t* out) {
  if (n < kLanes) {
    for (int x = 0; x < n; ++x) out[x] = score_at<std::uint8_t>(centre + x, offset);
    return;
  }
  Bytes32 floors;
  for (int i = 0; i < kLanes; ++i) floors[i] = floor;
  for (int x = 0;; x += kLanes) {
    x = std::min(x, n - kLanes);
    const Bytes32 s =
        may_score_above(centre + x, offset, floors) ? score_at<Bytes32>(centre + x, offset) : Bytes32{};
    std::memcpy(out + x, &s, kLanes);
    if (x == n - kLanes) break;
  }
}

void score_rows_baseline(const cv::Mat& image, const cv::Rect& area, const std::ptrdiff_t* offset,
                         std::uint8_t floor, cv::Mat& out) {
  for (int y = 0; y < area.height; ++y)
    score_row(image.ptr<std::uint8_t>(area.y + y) + area.x, offset, area.width, floor,
              out.ptr<std::uint8_t>(y));
}

#ifdef LRD_AVX2_COPIES
[[gnu::target("avx2")]] void score_rows_avx2(const cv::Mat& image, const cv::Rect& area,
                                             const std::ptrdiff_t* offset, std::uint8_t floor, cv::Mat& out) {
  for (int y = 0; y < area.height; ++y)
    score_row(image.ptr<std::uint8_t>(area.y + y) + area.x, offset, area.width, floor,
              out.ptr<std::uint8_t>(y));
}
#endif

// Non-maximum suppression as OpenCV's: a neighbour in the region that is a corner too and scores
// as high or higher suppresses a corner (ties suppress both). On the region's rows "masked" (a
// corner's score, 0 elsewhere and in a zero border), a pixel is a maximum iff its masked score is
// above every neighbour's, so one pass decides 32 pixels at once, edges included.
[[gnu::always_inline]] inline void mask_row(const std::uint8_t* scores, int n, std::uint8_t t,
                                            std::uint8_t* out) {
  for (int x = 0; x < n; ++x) out[x] = scores[x] > t ? scores[x] : 0;
}

// Flags (0xFF) the maxima of a row of `n` masked scores from masked[1] (masked[0] and masked[n + 1]
// are the border; every row is readable 32 bytes past n + 1).
[[gnu::always_inline]] inline void flag_maxima(const std::uint8_t* above, const std::uint8_t* row,
                                               const std::uint8_t* below, int n, std::uint8_t* flags) {
  for (int x = 0; x < n; x += kLanes) {
    const Bytes32 s = load<Bytes32>(row + x + 1);
    Bytes32 m = larger(load<Bytes32>(row + x), load<Bytes32>(row + x + 2));
    for (const std::uint8_t* r : {above, below})
      m = larger(m, larger(larger(load<Bytes32>(r + x), load<Bytes32>(r + x + 1)), load<Bytes32>(r + x + 2)));
    const Bytes32 found = reinterpret_cast<Bytes32>(s > m);  // s > m >= 0: s is a corner
    std::memcpy(flags + x, &found, kLanes);
  }
}

// The maxima of region `r` of `scores` at threshold t, as keypoints at `origin` + their place in
// `scores`. `buffer` holds three masked rows, a zero row and the flags.
[[gnu::always_inline]] inline void region_maxima(const cv::Mat& scores, const cv::Rect& r, std::uint8_t t,
                                                 cv::Point origin, std::vector<std::uint8_t>& buffer,
                                                 std::vector<cv::KeyPoint>& out) {
  const int n = r.width, stride = n + 2 + kLanes;
  buffer.assign(static_cast<std::size_t>(5 * stride), 0);
  std::uint8_t* zero = buffer.data() + 3 * stride;
  std::uint8_t* flags = zero + stride;
  auto masked = [&](int y) { return buffer.data() + (y - r.y) % 3 * stride; };
  auto fill = [&](int y) { mask_row(scores.ptr<std::uint8_t>(y) + r.x, n, t, masked(y) + 1); };
  fill(r.y);
  for (int y = r.y; y < r.y + r.height; ++y) {
    const bool last = y + 1 == r.y + r.height;
    if (!last) fill(y + 1);
    flag_maxima(y > r.y ? masked(y - 1) : zero, masked(y), last ? zero : masked(y + 1), n, flags);
    constexpr std::uint64_t kLowBits = ~std::uint64_t{0} / 255;  // one bit per flagged byte
    for (int x = 0; x < n; x += 8) {
      std::uint64_t word;
      std::memcpy(&word, flags + x, 8);
      for (std::uint64_t bits = word & kLowBits; bits != 0; bits &= bits - 1) {
        const int u = r.x + x + __builtin_ctzll(bits) / 8;
        if (u >= r.x + n) break;
        out.emplace_back(cv::Point2f(static_cast<float>(origin.x + u), static_cast<float>(origin.y + y)), 7.f,
                         -1.f, static_cast<float>(scores.at<std::uint8_t>(y, u) - 1));
      }
    }
  }
}

void maxima_baseline(const cv::Mat& scores, const cv::Rect& r, std::uint8_t t, cv::Point origin,
                     std::vector<std::uint8_t>& buffer, std::vector<cv::KeyPoint>& out) {
  region_maxima(scores, r, t, origin, buffer, out);
}

#ifdef LRD_AVX2_COPIES
[[gnu::target("avx2")]] void maxima_avx2(const cv::Mat& scores, const cv::Rect& r, std::uint8_t t,
                                         cv::Point origin, std::vector<std::uint8_t>& buffer,
                                         std::vector<cv::KeyPoint>& out) {
  region_maxima(scores, r, t, origin, buffer, out);
}
#endif

}  // namespace

void FastScores::compute(const cv::Mat& image, const cv::Rect& area, int floor) {
  CV_Assert(image.type() == CV_8UC1 && area.x >= 3 && area.y >= 3 && area.x + area.width <= image.cols - 3 &&
            area.y + area.height <= image.rows - 3 && floor >= 0 && floor < 256);
  floor_ = floor;
  area_ = area;
  scores_.create(area.size(), CV_8UC1);
  std::array<std::ptrdiff_t, 16> offset;
  for (int k = 0; k < 16; ++k)
    offset[k] = kCircle[k][0] + kCircle[k][1] * static_cast<std::ptrdiff_t>(image.step1());
#ifdef LRD_AVX2_COPIES
  if (util::cpu_has_avx2()) {
    score_rows_avx2(image, area, offset.data(), static_cast<std::uint8_t>(floor), scores_);
    return;
  }
#endif
  score_rows_baseline(image, area, offset.data(), static_cast<std::uint8_t>(floor), scores_);
}

void FastScores::corners(const cv::Rect& region, int threshold, std::vector<cv::KeyPoint>& out) {
  CV_Assert(threshold >= std::max(1, floor_) && threshold < 256 && (region & area_) == region);
  const cv::Rect r(region.x - area_.x, region.y - area_.y, region.width, region.height);  // in scores_
  const auto t = static_cast<std::uint8_t>(threshold);
#ifdef LRD_AVX2_COPIES
  if (util::cpu_has_avx2()) {
    maxima_avx2(scores_, r, t, area_.tl(), buffer_, out);
    return;
  }
#endif
  maxima_baseline(scores_, r, t, area_.tl(), buffer_, out);
}

}  // namespace lrd::features
