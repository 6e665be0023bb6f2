#pragma once
// Our bilinear resize for ONNX Resize (linear, half-pixel centres, fixed output size), as in the
// decoders of MediaPipe's selfie models. OpenCV 4.6 calls cv::resize once per channel plane, about
// 1 us each however small the plane (0.24 ms for selfie-landscape's three x2 up-samplings of
// 16-128 channels); ours does the x2 case, all planes in one pass, and any other size with
// cv::resize per plane as OpenCV does. Created through OwnKernelsScope (own_kernels.h).
#include <opencv2/dnn.hpp>
#include <vector>

namespace lrd::segmentation {

class LinearResizeLayer : public cv::dnn::Layer {
 public:
  explicit LinearResizeLayer(const cv::dnn::LayerParams& params);

  // True for OpenCV's ONNX Resize parameters of linear half-pixel interpolation to a fixed
  // "height" x "width" (OpenCV's "opencv_linear", or "bilinear" with half_pixel_centers).
  [[nodiscard]] static bool handles(const cv::dnn::LayerParams& params);

  bool supportBackend(int backend_id) override;
  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int required_outputs,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& internals) const override;
  void forward(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs,
               cv::OutputArrayOfArrays internals) override;

 private:
  int out_h_ = 0, out_w_ = 0;
};

}  // namespace lrd::segmentation
