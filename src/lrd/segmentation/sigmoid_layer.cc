#include "lrd/segmentation/sigmoid_layer.h"

#include <opencv2/core/hal/hal.hpp>

namespace lrd::segmentation {

SigmoidLayer::SigmoidLayer(const cv::dnn::LayerParams& params) {
  setParamsFrom(params);
  type = "OwnSigmoid";  // not "Sigmoid": nothing takes it for OpenCV's class
}

void SigmoidLayer::apply(const float* src, float* dst, int n) const {
  for (int i = 0; i < n; ++i) dst[i] = -src[i];
  cv::hal::exp32f(dst, dst, n);
  for (int i = 0; i < n; ++i) dst[i] = 1.0f / (1.0f + dst[i]);
}

}  // namespace lrd::segmentation
