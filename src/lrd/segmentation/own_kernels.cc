#include "lrd/segmentation/own_kernels.h"

#include <mutex>
#include <opencv2/dnn.hpp>
#include <opencv2/dnn/all_layers.hpp>

#include "lrd/segmentation/global_average_pooling_layer.h"
#include "lrd/segmentation/grouped_convolution_layer.h"
#include "lrd/segmentation/hard_swish_layer.h"
#include "lrd/segmentation/linear_resize_layer.h"
#include "lrd/segmentation/sigmoid_layer.h"
#include "lrd/segmentation/transposed_convolution_layer.h"
#include "lrd/segmentation/zero_padding_layer.h"

namespace lrd::segmentation {

namespace {

thread_local bool own_kernels_enabled = false;

cv::Ptr<cv::dnn::Layer> create_convolution(cv::dnn::LayerParams& params) {
  // OpenCV's own layer parses the parameters (kernel, strides, pads, dilations) for both.
  cv::Ptr<cv::dnn::BaseConvolutionLayer> opencv = cv::dnn::ConvolutionLayer::create(params);
  if (own_kernels_enabled && GroupedConvolutionLayer::handles(params, *opencv))
    return cv::makePtr<GroupedConvolutionLayer>(params, *opencv);
  return opencv;
}

cv::Ptr<cv::dnn::Layer> create_deconvolution(cv::dnn::LayerParams& params) {
  cv::Ptr<cv::dnn::BaseConvolutionLayer> opencv = cv::dnn::DeconvolutionLayer::create(params);
  if (own_kernels_enabled && TransposedConvolutionLayer::handles(params, *opencv))
    return cv::makePtr<TransposedConvolutionLayer>(params, *opencv);
  return opencv;
}

cv::Ptr<cv::dnn::Layer> create_sigmoid(cv::dnn::LayerParams& params) {
  if (own_kernels_enabled) return cv::makePtr<SigmoidLayer>(params);
  return cv::dnn::SigmoidLayer::create(params);
}

cv::Ptr<cv::dnn::Layer> create_hard_swish(cv::dnn::LayerParams& params) {
  if (own_kernels_enabled) return cv::makePtr<HardSwishLayer>(params);
  return cv::dnn::HardSwishLayer::create(params);
}

cv::Ptr<cv::dnn::Layer> create_resize(cv::dnn::LayerParams& params) {
  if (own_kernels_enabled && LinearResizeLayer::handles(params))
    return cv::makePtr<LinearResizeLayer>(params);
  return cv::dnn::ResizeLayer::create(params);
}

cv::Ptr<cv::dnn::Layer> create_pooling(cv::dnn::LayerParams& params) {
  if (own_kernels_enabled && GlobalAveragePoolingLayer::handles(params))
    return cv::makePtr<GlobalAveragePoolingLayer>(params);
  return cv::dnn::PoolingLayer::create(params);
}

cv::Ptr<cv::dnn::Layer> create_padding(cv::dnn::LayerParams& params) {
  if (own_kernels_enabled && ZeroPaddingLayer::handles(params)) return cv::makePtr<ZeroPaddingLayer>(params);
  return cv::dnn::PaddingLayer::create(params);
}

void register_own_kernels() {
  static std::once_flag once;
  // The factory keeps a stack of constructors per type and uses the newest.
  std::call_once(once, [] {
    cv::dnn::LayerFactory::registerLayer("Convolution", create_convolution);
    cv::dnn::LayerFactory::registerLayer("Deconvolution", create_deconvolution);
    cv::dnn::LayerFactory::registerLayer("Sigmoid", create_sigmoid);
    cv::dnn::LayerFactory::registerLayer("HardSwish", create_hard_swish);
    cv::dnn::LayerFactory::registerLayer("Resize", create_resize);
    cv::dnn::LayerFactory::registerLayer("Pooling", create_pooling);
    cv::dnn::LayerFactory::registerLayer("Padding", create_padding);
  });
}

}  // namespace

OwnKernelsScope::OwnKernelsScope() : previous_(own_kernels_enabled) {
  register_own_kernels();
  own_kernels_enabled = true;
}

OwnKernelsScope::~OwnKernelsScope() {
  own_kernels_enabled = previous_;
}

}  // namespace lrd::segmentation
