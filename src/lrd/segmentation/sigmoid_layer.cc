#include "lrd/segmentation/sigmoid_layer.h"

#include <opencv2/core/hal/hal.hpp>
#include <opencv2/core/utility.hpp>

#include <algorithm>

namespace lrd::segmentation {

namespace {

// dst = 1 / (1 + exp(-src)), n values; in place allowed.
void sigmoid(const float* src, float* dst, int n) {
  for (int i = 0; i < n; ++i) dst[i] = -src[i];
  cv::hal::exp32f(dst, dst, n);
  for (int i = 0; i < n; ++i) dst[i] = 1.0f / (1.0f + dst[i]);
}

}  // namespace

SigmoidLayer::SigmoidLayer(const cv::dnn::LayerParams& params) {
  setParamsFrom(params);
  // Not "Sigmoid", so that nothing takes it for OpenCV's class.
  type = "OwnSigmoid";
}

bool SigmoidLayer::supportBackend(int backend_id) {
  return backend_id == cv::dnn::DNN_BACKEND_OPENCV;
}

bool SigmoidLayer::getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int required_outputs,
                                   std::vector<cv::dnn::MatShape>& outputs,
                                   std::vector<cv::dnn::MatShape>& internals) const {
  cv::dnn::Layer::getMemoryShapes(inputs, required_outputs, outputs, internals);
  return true;  // in place, as OpenCV's activations
}

void SigmoidLayer::forward(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr,
                           cv::OutputArrayOfArrays /*internals*/) {
  std::vector<cv::Mat> inputs, outputs;
  inputs_arr.getMatVector(inputs);
  outputs_arr.getMatVector(outputs);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    CV_Assert(inputs[i].depth() == CV_32F && inputs[i].isContinuous() && outputs[i].isContinuous() &&
              inputs[i].total() == outputs[i].total());
    const float* src = inputs[i].ptr<float>();
    float* dst = outputs[i].ptr<float>();
    const int n = static_cast<int>(inputs[i].total());
    constexpr int kChunk = 4096;  // a task's share: in cache between the three passes
    cv::parallel_for_(cv::Range(0, (n + kChunk - 1) / kChunk), [&](const cv::Range& r) {
      for (int c = r.start; c < r.end; ++c) {
        const int begin = c * kChunk;
        sigmoid(src + begin, dst + begin, std::min(kChunk, n - begin));
      }
    });
  }
}

void SigmoidLayer::forwardSlice(const float* src, float* dst, int len, size_t plane_size, int cn0,
                                int cn1) const {
  for (int c = cn0; c < cn1; ++c, src += plane_size, dst += plane_size) sigmoid(src, dst, len);
}

}  // namespace lrd::segmentation
