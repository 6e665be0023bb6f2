#pragma once
// Our zero padding of the two spatial axes of an N x C x H x W tensor: OpenCV 4.6's ONNX importer
// puts such a layer before every convolution with uneven pads (TFLite's SAME padding at stride 2:
// four in selfie-landscape), and its generic layer took 0.03-0.1 ms each for a plain copy.
// Created through OwnKernelsScope (own_kernels.h).
#include <opencv2/dnn.hpp>
#include <vector>

namespace lrd::segmentation {

class ZeroPaddingLayer : public cv::dnn::Layer {
 public:
  explicit ZeroPaddingLayer(const cv::dnn::LayerParams& params);

  // True for OpenCV's Padding parameters of constant zero pads on the last two axes of 4 only.
  [[nodiscard]] static bool handles(const cv::dnn::LayerParams& params);

  bool supportBackend(int backend_id) override;
  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int required_outputs,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& internals) const override;
  void forward(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs,
               cv::OutputArrayOfArrays internals) override;

 private:
  int top_ = 0, bottom_ = 0, left_ = 0, right_ = 0;
};

}  // namespace lrd::segmentation
