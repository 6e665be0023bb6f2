#include "lrd/segmentation/global_average_pooling_layer.h"

#include <algorithm>
#include <cctype>
#include <opencv2/core/utility.hpp>
#include <string>

#include "lrd/segmentation/layer_data.h"

namespace lrd::segmentation {

GlobalAveragePoolingLayer::GlobalAveragePoolingLayer(const cv::dnn::LayerParams& params) {
  setParamsFrom(params);
  type = "GlobalAveragePooling";  // not "Pooling": nothing takes it for OpenCV's class
}

bool GlobalAveragePoolingLayer::handles(const cv::dnn::LayerParams& params) {
  // As OpenCV's importers set it for ONNX GlobalAveragePool (Caffe's global AVE pooling alike).
  if (!params.get<bool>("global_pooling", false)) return false;
  for (const char* partial : {"global_pooling_d", "global_pooling_h", "global_pooling_w", "kernel_size",
                              "kernel_h", "kernel_w", "pad", "stride"})
    if (params.has(partial)) return false;
  std::string pool = params.get<std::string>("pool", "max");
  std::transform(pool.begin(), pool.end(), pool.begin(), [](unsigned char c) { return std::tolower(c); });
  return pool == "ave";
}

bool GlobalAveragePoolingLayer::supportBackend(int backend_id) {
  return backend_id == cv::dnn::DNN_BACKEND_OPENCV;
}

bool GlobalAveragePoolingLayer::getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs,
                                                int /*required_outputs*/,
                                                std::vector<cv::dnn::MatShape>& outputs,
                                                std::vector<cv::dnn::MatShape>& /*internals*/) const {
  CV_Assert(inputs.size() == 1 && inputs[0].size() == 4);
  outputs.assign(1, cv::dnn::MatShape{inputs[0][0], inputs[0][1], 1, 1});
  return false;
}

void GlobalAveragePoolingLayer::forward(cv::InputArrayOfArrays inputs_arr,
                                        cv::OutputArrayOfArrays outputs_arr,
                                        cv::OutputArrayOfArrays /*internals*/) {
  LayerBlobs blobs = blobs_of(inputs_arr, outputs_arr);
  const cv::Mat& in = blobs.in;
  cv::Mat& out = blobs.out;
  const int planes = in.size[0] * in.size[1];
  const int n = in.size[2] * in.size[3];
  const float* src = in.ptr<float>();
  float* dst = out.ptr<float>();
  const auto pool = [&](const cv::Range& r) {
    for (int p = r.start; p < r.end; ++p) {
      // Eight running sums: one would chain every addition on the last (4 cycles each).
      const float* s = src + static_cast<std::size_t>(p) * n;
      float lanes[8] = {};
      int i = 0;
      for (; i + 8 <= n; i += 8)
        for (int k = 0; k < 8; ++k) lanes[k] += s[i + k];
      float sum = 0.0f;
      for (; i < n; ++i) sum += s[i];
      for (const float lane : lanes) sum += lane;
      dst[p] = sum / static_cast<float>(n);
    }
  };
  // A thread pool wake-up costs more than summing a small input.
  if (static_cast<std::size_t>(planes) * n < (1u << 16))
    pool(cv::Range(0, planes));
  else
    cv::parallel_for_(cv::Range(0, planes), pool);
}

}  // namespace lrd::segmentation
