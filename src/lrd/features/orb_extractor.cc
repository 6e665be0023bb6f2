#include "lrd/features/orb_extractor.h"

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <string>

#include "lrd/features/brief_pattern.h"
#include "lrd/util/cpu_features.h"
#include "lrd/util/error.h"

namespace lrd::features {
namespace {

constexpr int kHalfPatch = OrbExtractor::kPatchSize / 2;

const OrbParams& validated(const OrbParams& p) {
  auto fail = [](const std::string& what) { throw Error("ORB extractor: " + what); };
  if (p.n_features < 1) fail("n_features must be >= 1, got " + std::to_string(p.n_features));
  if (p.min_th_fast < 1 || p.ini_th_fast < p.min_th_fast) {
    fail("FAST thresholds must satisfy 1 <= min_th_fast <= ini_th_fast, got " +
         std::to_string(p.min_th_fast) + " and " + std::to_string(p.ini_th_fast));
  }
  return p;  // n_levels and scale_factor are checked by ImagePyramid
}

// Intensity-centroid orientation (Rosin 1999; Rublee et al. 2011, sec. 3.2): the moments
// m10 = sum u I and m01 = sum v I over the disc, each row a 32-pixel dot product with the disc's
// weights, which vectorises (integers: the same sums in any order).
[[gnu::always_inline]] inline void orient(const cv::Mat& image, cv::KeyPoint& kp,
                                          const OrbExtractor::DiscWeights& disc) {
  const std::uint8_t* centre = image.ptr<std::uint8_t>(cvRound(kp.pt.y)) + cvRound(kp.pt.x);
  const auto step = static_cast<std::ptrdiff_t>(image.step1());
  int m10 = 0, m01 = 0;
  for (int v = -kHalfPatch; v <= kHalfPatch; ++v) {
    const std::uint8_t* row = centre + v * step - kHalfPatch;  // to u = 16, inside the level: kEdge > 16
    const std::int16_t* by_u = disc.u[v + kHalfPatch];
    const std::int16_t* inside = disc.inside[v + kHalfPatch];
    int row_m10 = 0, row_sum = 0;
    for (int x = 0; x < 32; ++x) {
      const std::int16_t pixel = row[x];
      row_m10 += by_u[x] * pixel;
      row_sum += inside[x] * pixel;
    }
    m10 += row_m10;
    m01 += v * row_sum;
  }
  float angle =
      std::atan2(static_cast<float>(m01), static_cast<float>(m10)) * (180.0f / std::numbers::pi_v<float>);
  if (angle < 0.0f) angle += 360.0f;
  if (angle >= 360.0f) angle = 0.0f;
  kp.angle = angle;
}

// Steered BRIEF on the smoothed level image, one 32-byte row; pattern_x, pattern_y: the pattern's
// points in turn.
[[gnu::always_inline]] inline void describe(const cv::Mat& smoothed, const cv::KeyPoint& kp,
                                            const float* pattern_x, const float* pattern_y,
                                            std::uint8_t* row) {
  const float theta = kp.angle * (std::numbers::pi_v<float> / 180.0f);
  const float c = std::cos(theta), s = std::sin(theta);
  const std::uint8_t* centre = smoothed.ptr<std::uint8_t>(cvRound(kp.pt.y)) + cvRound(kp.pt.x);
  const int step = static_cast<int>(smoothed.step1());
  // The pattern turned by the keypoint's angle (steered BRIEF, Rublee et al. 2011, sec. 4.1),
  // rounded half away from zero; written as one flat loop so that it vectorises.
  std::array<int, 2 * OrbExtractor::kDescriptorBits> offset;
  for (int i = 0; i < 2 * OrbExtractor::kDescriptorBits; ++i) {
    const float x = pattern_x[i] * c - pattern_y[i] * s;
    const float y = pattern_x[i] * s + pattern_y[i] * c;
    offset[i] =
        static_cast<int>(y + std::copysign(0.5f, y)) * step + static_cast<int>(x + std::copysign(0.5f, x));
  }
  for (int byte = 0; byte < OrbExtractor::kDescriptorBytes; ++byte) {
    unsigned value = 0;
    for (int bit = 0; bit < 8; ++bit) {
      const int i = 2 * (8 * byte + bit);
      value |= static_cast<unsigned>(centre[offset[i]] < centre[offset[i + 1]]) << bit;
    }
    row[byte] = static_cast<std::uint8_t>(value);
  }
}

// A level's images, and the pattern of orientation and description.
struct LevelImages {
  const cv::Mat& image;
  const cv::Mat& smoothed;
  const ImagePyramid& pyramid;
  int level;
};
struct Pattern {
  const OrbExtractor::DiscWeights* disc;
  const float* x;
  const float* y;
};
// Orientation and descriptor of every keypoint chosen on one level, written to `keypoints` and
// `descriptors` from row `row` on (level-0 coordinates). Inlined into two copies below, one
// compiled for AVX2 (twice the vector width for the moments and the pattern's rotation; no FMA, so
// the same bits as the SSE2 baseline).
[[gnu::always_inline]] inline void describe_level(const LevelImages& in, const Pattern& pattern,
                                                  std::vector<cv::KeyPoint>& chosen, int row,
                                                  std::vector<cv::KeyPoint>& keypoints,
                                                  cv::Mat& descriptors) {
  const float size = static_cast<float>(OrbExtractor::kPatchSize) * in.pyramid.scale_factors()[in.level];
  for (cv::KeyPoint& kp : chosen) {
    orient(in.image, kp, *pattern.disc);
    describe(in.smoothed, kp, pattern.x, pattern.y, descriptors.ptr<std::uint8_t>(row));
    keypoints[row++] =
        cv::KeyPoint(in.pyramid.to_base(in.level, kp.pt.x, kp.pt.y), size, kp.angle, kp.response, in.level);
  }
}

void describe_level_baseline(const LevelImages& in, const Pattern& pattern, std::vector<cv::KeyPoint>& chosen,
                             int row, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
  describe_level(in, pattern, chosen, row, keypoints, descriptors);
}

#ifdef LRD_AVX2_COPIES
[[gnu::target("avx2")]] void describe_level_avx2(const LevelImages& in, const Pattern& pattern,
                                                 std::vector<cv::KeyPoint>& chosen, int row,
                                                 std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
  describe_level(in, pattern, chosen, row, keypoints, descriptors);
}
#endif

}  // namespace

OrbExtractor::OrbExtractor(const OrbParams& params)
    : params_(validated(params)), pyramid_(params.n_levels, params.scale_factor) {
  const int n = params_.n_levels;
  for (float s : pyramid_.scale_factors()) {
    sigma2_.push_back(s * s);
    inv_sigma2_.push_back(1.0f / (s * s));
  }
  // The budget falls geometrically with the level's linear scale (ORB-SLAM2): level i gets a
  // share proportional to scale_factor^-i; level 0 takes what rounding leaves.
  per_level_.assign(n, 0);
  const double f = 1.0 / params_.scale_factor;
  const double first = n == 1 ? params_.n_features : params_.n_features * (1.0 - f) / (1.0 - std::pow(f, n));
  int assigned = 0;
  for (int i = 1; i < n; ++i) {
    per_level_[i] = static_cast<int>(std::lround(first * std::pow(f, i)));
    assigned += per_level_[i];
  }
  per_level_[0] = std::max(0, params_.n_features - assigned);

  // The circular orientation patch: |u| <= u_max[|v|], i.e. u^2 + v^2 <= (R + 1/2)^2. A rule on
  // u^2 + v^2 keeps the disc symmetric under 90-degree turns, so turning the image by 90 degrees
  // turns the angle by exactly 90.
  const int limit = kHalfPatch * kHalfPatch + kHalfPatch;  // floor((R + 1/2)^2)
  for (int v = -kHalfPatch; v <= kHalfPatch; ++v) {
    int u_max = 0;
    while ((u_max + 1) * (u_max + 1) + v * v <= limit) ++u_max;
    for (int x = 0; x < 32; ++x) {
      const int u = x - kHalfPatch;
      const bool inside = std::abs(u) <= u_max;  // x = 31 (u = 16) is always outside
      disc_.u[v + kHalfPatch][x] = static_cast<std::int16_t>(inside ? u : 0);
      disc_.inside[v + kHalfPatch][x] = inside ? 1 : 0;
    }
  }
  work_.resize(n);
  int i = 0;
  for (const BriefPair& p : brief_pattern()) {
    pattern_x_[i] = p.x1, pattern_y_[i++] = p.y1;
    pattern_x_[i] = p.x2, pattern_y_[i++] = p.y2;
  }
}

void OrbExtractor::detect(int level, const cv::Mat& mask, LevelWork& work) const {
  std::vector<cv::KeyPoint>& corners = work.corners;
  corners.clear();
  const cv::Mat& image = pyramid_.level(level);
  // Corners may lie in [kEdge, size - kEdge); FAST reads 3 more pixels around what it scores.
  const cv::Rect area(kEdge, kEdge, image.cols - 2 * kEdge, image.rows - 2 * kEdge);
  if (area.width < 1 || area.height < 1) return;
  const int cells_x = std::max(1, area.width / kCellSize);
  const int cells_y = std::max(1, area.height / kCellSize);
  const int cell_w = (area.width + cells_x - 1) / cells_x;
  const int cell_h = (area.height + cells_y - 1) / cells_y;
  work.cell_strong.assign(static_cast<std::size_t>(cells_x) * cells_y, 0);

  // Keeps the unmasked FAST corners of `region` (level coordinates) at `threshold`.
  work.scores.compute(image, area, params_.min_th_fast);
  auto collect = [&](const cv::Rect& region, int threshold) {
    work.found.clear();
    work.scores.corners(region, threshold, work.found);
    for (const cv::KeyPoint& kp : work.found) {
      if (!mask.empty()) {
        const cv::Point2f p = pyramid_.to_base(level, kp.pt.x, kp.pt.y);
        const int mx = std::clamp(cvRound(p.x), 0, mask.cols - 1);
        const int my = std::clamp(cvRound(p.y), 0, mask.rows - 1);
        if (mask.at<std::uint8_t>(my, mx) != 0) continue;
      }
      corners.push_back(kp);
    }
  };

  // High threshold over the whole level first; then the low one, as ORB-SLAM2 does, only in the
  // cells left without a corner, so low-contrast regions still get features without letting weak
  // corners crowd strong ones elsewhere.
  collect(area, params_.ini_th_fast);
  for (const cv::KeyPoint& kp : corners) {
    const int cx = (static_cast<int>(kp.pt.x) - area.x) / cell_w;
    const int cy = (static_cast<int>(kp.pt.y) - area.y) / cell_h;
    work.cell_strong[static_cast<std::size_t>(cy) * cells_x + cx] = 1;
  }
  for (int cy = 0; cy < cells_y; ++cy) {
    const char* strong = work.cell_strong.data() + static_cast<std::size_t>(cy) * cells_x;
    // A run of weak cells in a row is one region: its corners are suppressed only by neighbours
    // inside it, as when each run was searched by its own cv::FAST call.
    for (int cx = 0; cx < cells_x;) {
      if (strong[cx]) {
        ++cx;
        continue;
      }
      const int first = cx;
      while (cx < cells_x && !strong[cx]) ++cx;
      const cv::Rect run =
          cv::Rect(area.x + first * cell_w, area.y + cy * cell_h, (cx - first) * cell_w, cell_h) & area;
      if (!run.empty()) collect(run, params_.min_th_fast);
    }
  }
}

void OrbExtractor::check_input(const cv::Mat& grey, const cv::Mat& mask) const {
  if (grey.empty() || grey.type() != CV_8UC1)
    throw Error("ORB extractor: the image must be a non-empty CV_8UC1");
  if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != grey.size())) {
    throw Error("ORB extractor: the mask must be CV_8UC1 of the image's size");
  }
}

void OrbExtractor::extract(const cv::Mat& grey, const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints,
                           cv::Mat& descriptors) {
  check_input(grey, mask);
  detect_and_smooth(grey, mask);
  finish(cv::Mat(), keypoints, descriptors);
}

void OrbExtractor::detect(const cv::Mat& grey) {
  check_input(grey, cv::Mat());
  detect_and_smooth(grey, cv::Mat());
}

void OrbExtractor::detect_and_smooth(const cv::Mat& grey, const cv::Mat& mask) {
  // A level's corners and its smoothing (for the descriptors) need only its image: both go to TBB
  // as soon as the level is built, level 0 (the input itself, a third of the pixels) first. The
  // helper thread takes the oldest tasks while this one builds the pyramid (a chain of resizes,
  // a quarter of the work), then both finish what is left.
  tbb::task_group level_tasks;
  auto start_level = [&](int level) {
    level_tasks.run([this, &mask, level] { detect(level, mask, work_[level]); });
    level_tasks.run(
        [this, level] { work_[level].smoother.smooth(pyramid_.level(level), work_[level].smoothed); });
  };
  pyramid_.set_base(grey);
  start_level(0);
  for (int level = 1; level < levels(); ++level) {
    // Isolated: cv::resize's own parallel loop must not pick up a level's task here, which
    // would hold up the chain the other levels wait for.
    tbb::this_task_arena::isolate([&] { pyramid_.build_level(level); });
    start_level(level);
  }
  level_tasks.wait();
}

void OrbExtractor::describe_detected(const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints,
                                     cv::Mat& descriptors) {
  if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != pyramid_.level(0).size()))
    throw Error("ORB extractor: the mask must be CV_8UC1 of the image's size");
  finish(mask, keypoints, descriptors);
}

void OrbExtractor::describe_chosen(int level) {
  LevelWork& w = work_[level];
  w.keypoints.resize(w.chosen.size());
  w.descriptors.create(static_cast<int>(w.chosen.size()), kDescriptorBytes, CV_8U);
  if (w.chosen.empty()) return;
  // Smoothed (detect_and_smooth) so that the binary tests are robust to noise (Rublee et al.
  // 2011, sec. 4).
  const LevelImages in{pyramid_.level(level), w.smoothed, pyramid_, level};
  const Pattern pattern{&disc_, pattern_x_.data(), pattern_y_.data()};
#ifdef LRD_AVX2_COPIES
  if (util::cpu_has_avx2()) {
    describe_level_avx2(in, pattern, w.chosen, 0, w.keypoints, w.descriptors);
    return;
  }
#endif
  describe_level_baseline(in, pattern, w.chosen, 0, w.keypoints, w.descriptors);
}

void OrbExtractor::finish(const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
  const int n = levels();
  // Coarse to fine: what a level cannot fill passes to the next finer one, which has more corners,
  // so low-texture images still get close to n_features. Each level is described on TBB's
  // helper thread as soon as its keypoints are chosen, while this thread chooses the next finer
  // level's (the helper wakes behind that work, and the two threads end together).
  tbb::task_group describing;
  int carry = 0;
  for (int level = n - 1; level >= 0; --level) {
    const cv::Mat& image = pyramid_.level(level);
    LevelWork& w = work_[level];
    if (!mask.empty()) {
      std::erase_if(w.corners, [&](const cv::KeyPoint& kp) {
        const cv::Point2f p = pyramid_.to_base(level, kp.pt.x, kp.pt.y);
        const int mx = std::clamp(cvRound(p.x), 0, mask.cols - 1);
        const int my = std::clamp(cvRound(p.y), 0, mask.rows - 1);
        return mask.at<std::uint8_t>(my, mx) != 0;
      });
    }
    w.chosen.clear();
    const int wanted = per_level_[level] + carry;
    const cv::Rect2f area(kEdge, kEdge, static_cast<float>(image.cols - 2 * kEdge),
                          static_cast<float>(image.rows - 2 * kEdge));
    for (int i : distributor_.select(w.corners, area, wanted)) w.chosen.push_back(w.corners[i]);
    carry = wanted - static_cast<int>(w.chosen.size());
    describing.run([this, level] { describe_chosen(level); });
  }
  describing.wait();

  // In level order, as the contract says.
  std::size_t total = 0;
  for (const LevelWork& w : work_) total += w.keypoints.size();
  keypoints.clear();
  keypoints.reserve(total);
  descriptors.create(static_cast<int>(total), kDescriptorBytes, CV_8U);
  int row = 0;
  for (const LevelWork& w : work_) {
    keypoints.insert(keypoints.end(), w.keypoints.begin(), w.keypoints.end());
    if (w.descriptors.rows > 0) w.descriptors.copyTo(descriptors.rowRange(row, row + w.descriptors.rows));
    row += w.descriptors.rows;
  }
}

}  // namespace lrd::features
