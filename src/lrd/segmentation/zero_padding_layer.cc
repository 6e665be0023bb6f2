#include "lrd/segmentation/zero_padding_layer.h"

#include <algorithm>
#include <opencv2/core/utility.hpp>
#include <string>

#include "lrd/segmentation/layer_data.h"

namespace lrd::segmentation {

ZeroPaddingLayer::ZeroPaddingLayer(const cv::dnn::LayerParams& params) {
  setParamsFrom(params);
  type = "ZeroPadding";  // not "Padding": nothing takes it for OpenCV's class
  const cv::dnn::DictValue& p = params.get("paddings");
  top_ = p.get<int>(4);
  bottom_ = p.get<int>(5);
  left_ = p.get<int>(6);
  right_ = p.get<int>(7);
}

bool ZeroPaddingLayer::handles(const cv::dnn::LayerParams& params) {
  if (!params.has("paddings") || params.has("input_dims")) return false;
  if (params.get<std::string>("type", "constant") != "constant" || params.get<float>("value", 0.0f) != 0.0f)
    return false;
  const cv::dnn::DictValue& p = params.get("paddings");
  if (p.size() != 8) return false;
  for (int i = 0; i < 8; ++i)
    if (p.get<int>(i) < 0 || (i < 4 && p.get<int>(i) != 0)) return false;
  return true;
}

bool ZeroPaddingLayer::supportBackend(int backend_id) {
  return backend_id == cv::dnn::DNN_BACKEND_OPENCV;
}

bool ZeroPaddingLayer::getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int /*required_outputs*/,
                                       std::vector<cv::dnn::MatShape>& outputs,
                                       std::vector<cv::dnn::MatShape>& /*internals*/) const {
  CV_Assert(inputs.size() == 1 && inputs[0].size() == 4);
  outputs.assign(1, cv::dnn::MatShape{inputs[0][0], inputs[0][1], inputs[0][2] + top_ + bottom_,
                                      inputs[0][3] + left_ + right_});
  return false;
}

void ZeroPaddingLayer::forward(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr,
                               cv::OutputArrayOfArrays /*internals*/) {
  LayerBlobs blobs = blobs_of(inputs_arr, outputs_arr);
  const cv::Mat& in = blobs.in;
  cv::Mat& out = blobs.out;
  const int planes = in.size[0] * in.size[1], h = in.size[2], w = in.size[3];
  const int oh = out.size[2], ow = out.size[3];
  const float* src = in.ptr<float>();
  float* dst = out.ptr<float>();
  const auto pad = [&](const cv::Range& r) {
    for (int p = r.start; p < r.end; ++p) {
      const float* s = src + static_cast<std::size_t>(p) * h * w;
      float* d = dst + static_cast<std::size_t>(p) * oh * ow;
      std::fill(d, d + static_cast<std::size_t>(top_) * ow, 0.0f);
      for (int y = 0; y < h; ++y) {
        float* row = d + static_cast<std::size_t>(y + top_) * ow;
        std::fill(row, row + left_, 0.0f);
        std::copy(s + static_cast<std::size_t>(y) * w, s + static_cast<std::size_t>(y + 1) * w, row + left_);
        std::fill(row + left_ + w, row + ow, 0.0f);
      }
      std::fill(d + static_cast<std::size_t>(top_ + h) * ow, d + static_cast<std::size_t>(oh) * ow, 0.0f);
    }
  };
  // A thread pool wake-up costs more than copying a small tensor.
  if (out.total() < (1u << 17))
    pad(cv::Range(0, planes));
  else
    cv::parallel_for_(cv::Range(0, planes), pad);
}

}  // namespace lrd::segmentation
