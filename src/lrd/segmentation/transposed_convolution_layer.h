#pragma once
// Our kernel for a transposed convolution whose kernel equals its stride (each input pixel paints
// its own kernel-sized block of the output: an learned up-sampling, as at the end of MediaPipe's
// selfie models, 16 channels to 1 at x2). OpenCV 4.6 runs it as a GEMM and a col2im pass, 0.15 ms
// on selfie-landscape, ours sums each output row directly. Created through OwnKernelsScope
// (own_kernels.h).
#include <opencv2/dnn.hpp>
#include <opencv2/dnn/all_layers.hpp>
#include <vector>

namespace lrd::segmentation {

class TransposedConvolutionLayer : public cv::dnn::Layer {
 public:
  // `params` as OpenCV's importers fill them for a "Deconvolution" layer (weights in_channels x
  // out_channels x kernel_h x kernel_w); `geometry` is OpenCV's own parse of them.
  TransposedConvolutionLayer(const cv::dnn::LayerParams& params,
                             const cv::dnn::BaseConvolutionLayer& geometry);

  // True for a 2-D transposed convolution of one group, weights in the model, kernel == stride,
  // no pads, no output padding, no dilation.
  [[nodiscard]] static bool handles(const cv::dnn::LayerParams& params,
                                    const cv::dnn::BaseConvolutionLayer& geometry);

  bool supportBackend(int backend_id) override;
  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int required_outputs,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& internals) const override;
  bool setActivation(const cv::Ptr<cv::dnn::ActivationLayer>& layer) override;
  void forward(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs,
               cv::OutputArrayOfArrays internals) override;

 private:
  int in_channels_ = 0, out_channels_ = 0, kernel_h_ = 0, kernel_w_ = 0;
  std::vector<float> weights_;  // in_channels x out_channels x kernel_h x kernel_w
  std::vector<float> bias_;     // out_channels
  cv::Ptr<cv::dnn::ActivationLayer> activation_;
};

}  // namespace lrd::segmentation
