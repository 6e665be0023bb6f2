#pragma once
// Our global average pooling (N x C x H x W to N x C x 1 x 1), the squeeze of the selfie models'
// ten squeeze-and-excitation blocks. OpenCV 4.6's pooling layer spends about 13 us on each however
// small the input; the sums themselves take 1-2 us. Created through OwnKernelsScope (own_kernels.h).
#include <opencv2/dnn.hpp>
#include <vector>

namespace lrd::segmentation {

class GlobalAveragePoolingLayer : public cv::dnn::Layer {
 public:
  explicit GlobalAveragePoolingLayer(const cv::dnn::LayerParams& params);

  // True for average pooling over the whole map, as OpenCV's importers describe it.
  [[nodiscard]] static bool handles(const cv::dnn::LayerParams& params);

  bool supportBackend(int backend_id) override;
  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int required_outputs,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& internals) const override;
  void forward(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs,
               cv::OutputArrayOfArrays internals) override;
};

}  // namespace lrd::segmentation
