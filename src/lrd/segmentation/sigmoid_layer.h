#pragma once
// Our logistic sigmoid: OpenCV 4.6 evaluates it one scalar exp at a time (5 ns a value; 0.19 ms on
// the 144x256 output of selfie-landscape), ours with OpenCV's vectorized exp. An activation layer
// like OpenCV's, so that it fuses into the layer before it the same way. Created through
// OwnKernelsScope (own_kernels.h).
#include <opencv2/dnn.hpp>
#include <opencv2/dnn/all_layers.hpp>

#include <vector>

namespace lrd::segmentation {

class SigmoidLayer : public cv::dnn::ActivationLayer {
 public:
  explicit SigmoidLayer(const cv::dnn::LayerParams& params);

  bool supportBackend(int backend_id) override;
  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int required_outputs,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& internals) const override;
  void forward(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs,
               cv::OutputArrayOfArrays internals) override;
  // 1 / (1 + exp(-x)) on `len` values of each channel plane cn0..cn1-1 (OpenCV's contract).
  void forwardSlice(const float* src, float* dst, int len, size_t plane_size, int cn0, int cn1) const override;
};

}  // namespace lrd::segmentation
