#include "lrd/segmentation/fast_activation_layer.h"

#include <algorithm>
#include <opencv2/core/utility.hpp>

namespace lrd::segmentation {

bool FastActivationLayer::supportBackend(int backend_id) {
  return backend_id == cv::dnn::DNN_BACKEND_OPENCV;
}

bool FastActivationLayer::getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int required_outputs,
                                          std::vector<cv::dnn::MatShape>& outputs,
                                          std::vector<cv::dnn::MatShape>& internals) const {
  cv::dnn::Layer::getMemoryShapes(inputs, required_outputs, outputs, internals);
  return true;  // in place, as OpenCV's activations
}

void FastActivationLayer::forward(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr,
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
    constexpr int kChunk = 16384;  // a task's share; smaller inputs stay on the calling thread
    if (n <= kChunk) {
      apply(src, dst, n);
      continue;
    }
    cv::parallel_for_(cv::Range(0, (n + kChunk - 1) / kChunk), [&](const cv::Range& r) {
      for (int c = r.start; c < r.end; ++c) {
        const int begin = c * kChunk;
        apply(src + begin, dst + begin, std::min(kChunk, n - begin));
      }
    });
  }
}

void FastActivationLayer::forwardSlice(const float* src, float* dst, int len, size_t plane_size, int cn0,
                                       int cn1) const {
  for (int c = cn0; c < cn1; ++c, src += plane_size, dst += plane_size) apply(src, dst, len);
}

}  // namespace lrd::segmentation
