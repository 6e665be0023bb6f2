#include "lrd/features/gaussian_smoother.h"

#include <cstring>

#include "lrd/util/cpu_features.h"

namespace lrd::features {
namespace {

// Rows [3, h - 3) of dst: the separable 7-tap filter, vertical pass into `col` then horizontal.
// Inlined into two copies below, one compiled for AVX2, which doubles the 16-bit lanes the loops
// vectorise to (the baseline x86-64 build has SSE2 only): the same arithmetic, the same result.
[[gnu::always_inline]] inline void smooth_rows(const cv::Mat& src, cv::Mat& dst, std::uint8_t* col) {
  constexpr unsigned w0 = GaussianSmoother::kTaps[0], w1 = GaussianSmoother::kTaps[1],
                     w2 = GaussianSmoother::kTaps[2], w3 = GaussianSmoother::kTaps[3];
  const int w = src.cols, h = src.rows;
  for (int y = 3; y < h - 3; ++y) {
    const std::uint8_t* r[7];
    for (int k = 0; k < 7; ++k) r[k] = src.ptr<std::uint8_t>(y + k - 3);
    // Vertical pass, rounded to 8 bits: every product sum fits 16 bits, so the loop vectorises
    // with 16-bit lanes.
    for (int x = 0; x < w; ++x) {
      const unsigned s =
          w0 * r[3][x] + w1 * (r[2][x] + r[4][x]) + w2 * (r[1][x] + r[5][x]) + w3 * (r[0][x] + r[6][x]);
      col[x] = static_cast<std::uint8_t>((s + 128u) >> 8);
    }
    std::uint8_t* out = dst.ptr<std::uint8_t>(y);
    const std::uint8_t* in = src.ptr<std::uint8_t>(y);
    for (int x = 0; x < 3; ++x) {
      out[x] = in[x];
      out[w - 1 - x] = in[w - 1 - x];
    }
    for (int x = 3; x < w - 3; ++x) {
      const unsigned s = w0 * col[x] + w1 * (col[x - 1] + col[x + 1]) + w2 * (col[x - 2] + col[x + 2]) +
                         w3 * (col[x - 3] + col[x + 3]);
      out[x] = static_cast<std::uint8_t>((s + 128u) >> 8);
    }
  }
}

void smooth_rows_baseline(const cv::Mat& src, cv::Mat& dst, std::uint8_t* col) {
  smooth_rows(src, dst, col);
}

#ifdef LRD_AVX2_COPIES
[[gnu::target("avx2")]] void smooth_rows_avx2(const cv::Mat& src, cv::Mat& dst, std::uint8_t* col) {
  smooth_rows(src, dst, col);
}
#endif

}  // namespace

void GaussianSmoother::smooth(const cv::Mat& src, cv::Mat& dst) {
  CV_Assert(src.type() == CV_8UC1 && src.data != dst.data);
  dst.create(src.size(), CV_8UC1);
  const int w = src.cols, h = src.rows;
  if (w < 7 || h < 7) {
    src.copyTo(dst);
    return;
  }
  for (int y = 0; y < 3; ++y) {
    std::memcpy(dst.ptr(y), src.ptr(y), w);
    std::memcpy(dst.ptr(h - 1 - y), src.ptr(h - 1 - y), w);
  }
  column_.resize(w);
#ifdef LRD_AVX2_COPIES
  if (util::cpu_has_avx2()) {
    smooth_rows_avx2(src, dst, column_.data());
    return;
  }
#endif
  smooth_rows_baseline(src, dst, column_.data());
}

}  // namespace lrd::features
