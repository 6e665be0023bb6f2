#include "lrd/segmentation/hard_swish_layer.h"

#include <algorithm>
#include <opencv2/core/hal/intrin.hpp>

namespace lrd::segmentation {

HardSwishLayer::HardSwishLayer(const cv::dnn::LayerParams& params) {
  setParamsFrom(params);
  type = "OwnHardSwish";  // not "HardSwish": nothing takes it for OpenCV's class
}

void HardSwishLayer::apply(const float* src, float* dst, int n) const {
  // OpenCV's arithmetic (x / 6 + 0.5, clamped to [0, 1], times x), so the same floats; written
  // with SIMD types because GCC does not if-convert the clamp (trapping math).
  int i = 0;
#if CV_SIMD128
  const cv::v_float32x4 six = cv::v_setall_f32(6.0f), half = cv::v_setall_f32(0.5f);
  const cv::v_float32x4 zero = cv::v_setzero_f32(), one = cv::v_setall_f32(1.0f);
  for (; i + 4 <= n; i += 4) {
    const cv::v_float32x4 x = cv::v_load(src + i);
    const cv::v_float32x4 gate = cv::v_min(cv::v_max(x / six + half, zero), one);
    cv::v_store(dst + i, x * gate);
  }
#endif
  for (; i < n; ++i) dst[i] = src[i] * std::min(std::max(src[i] / 6.0f + 0.5f, 0.0f), 1.0f);
}

}  // namespace lrd::segmentation
