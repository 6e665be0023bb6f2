#pragma once
// Our kernel for the convolutions OpenCV 4.6 DNN runs on its slow generic (im2row) path: those
// whose groups each read only a few input channels. OpenCV has a fast path for 3x3 depthwise
// convolutions only; MediaPipe's selfie models use 5x5 ones, which on selfie-landscape's 9x16 maps
// took 0.2-0.3 ms each for 0.5 M multiply-adds (a quarter of the whole network), and ours take
// 0.05 ms. Its first layer (RGB to 16 channels, 3x3, stride 2) gets an AVX2 kernel that computes
// four output channels per input load. Created through OwnKernelsScope (own_kernels.h).
#include <opencv2/dnn.hpp>
#include <opencv2/dnn/all_layers.hpp>
#include <vector>

namespace lrd::segmentation {

class GroupedConvolutionLayer : public cv::dnn::Layer {
 public:
  // `params` as OpenCV's importers fill them for a "Convolution" layer; `geometry` is OpenCV's own
  // parse of them (kernel, strides, pads, dilations).
  GroupedConvolutionLayer(const cv::dnn::LayerParams& params, const cv::dnn::BaseConvolutionLayer& geometry);

  // True when this layer computes `geometry` faster than OpenCV: a 2-D convolution with weights
  // given in the model, explicit pads, and either one input channel per group (depthwise) with a
  // kernel other than OpenCV's fast 3x3, or (on CPUs with AVX2 and FMA) at most 4 input channels
  // per group, output channels in fours and a kernel larger than 1x1 (a first layer on RGB).
  [[nodiscard]] static bool handles(const cv::dnn::LayerParams& params,
                                    const cv::dnn::BaseConvolutionLayer& geometry);

  bool supportBackend(int backend_id) override;
  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int required_outputs,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& internals) const override;
  // A following activation (ReLU, hard-swish, ...) runs on each output plane while it is in cache.
  bool setActivation(const cv::Ptr<cv::dnn::ActivationLayer>& layer) override;
  // Plans the padded planes and the kernel taps for the shapes OpenCV settled on: once, not per frame.
  void finalize(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs) override;
  void forward(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs,
               cv::OutputArrayOfArrays internals) override;

  // Each padded input plane stored as stride_w column phases (see the .cc).
  struct PlaneLayout {
    int in_h = 0, in_w = 0, out_h = 0, out_w = 0;
    int sh = 1, sw = 1, pt = 0, pl = 0;
    int phase_len = 0;           // floats in one phase row
    std::size_t row_stride = 0;  // floats in one padded row (all its phases)
    std::size_t plane_size = 0;  // floats in one padded plane
    std::vector<int> tap_at;     // per tap (channel, i, j): offset from output row 0's first input
  };

 private:
  void plan(const cv::dnn::MatShape& in, const cv::dnn::MatShape& out);

  int in_channels_ = 0, out_channels_ = 0, groups_ = 1;
  int kernel_h_ = 0, kernel_w_ = 0, stride_h_ = 1, stride_w_ = 1, dilation_h_ = 1, dilation_w_ = 1;
  int pad_top_ = 0, pad_left_ = 0, pad_bottom_ = 0, pad_right_ = 0;
  std::vector<float> weights_;  // out_channels x (in_channels / groups) x kernel_h x kernel_w
  std::vector<float> bias_;     // out_channels
  cv::Ptr<cv::dnn::ActivationLayer> activation_;
  std::vector<float> weights_x4_;  // the AVX2 kernel's: output channels in fours, interleaved per tap
  PlaneLayout layout_;
  std::vector<float> padded_;  // the padded input planes, in stride phases
};

}  // namespace lrd::segmentation
