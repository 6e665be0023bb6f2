#include "lrd/segmentation/transposed_convolution_layer.h"

#include <algorithm>
#include <opencv2/core/utility.hpp>

#include "lrd/segmentation/layer_data.h"

namespace lrd::segmentation {

TransposedConvolutionLayer::TransposedConvolutionLayer(const cv::dnn::LayerParams& params,
                                                       const cv::dnn::BaseConvolutionLayer& geometry)
    : cv::dnn::Layer(params) {
  // Not "Deconvolution": OpenCV's own code may take every layer of that type for its class.
  type = "TransposedConvolution";
  const cv::Mat& w = params.blobs[0];
  in_channels_ = w.size[0];
  out_channels_ = w.size[1];
  kernel_h_ = static_cast<int>(geometry.kernel_size[0]);
  kernel_w_ = static_cast<int>(geometry.kernel_size[1]);
  weights_ = weights_of(params);
  bias_ = bias_of(params, out_channels_);
}

bool TransposedConvolutionLayer::handles(const cv::dnn::LayerParams& params,
                                         const cv::dnn::BaseConvolutionLayer& geometry) {
  if (geometry.kernel_size.size() != 2 || !geometry.padMode.empty() || params.blobs.empty()) return false;
  const cv::Mat& w = params.blobs[0];
  if (w.dims != 4 || w.depth() != CV_32F || params.get<int>("group", 1) != 1) return false;
  if (params.get<int>("num_output", w.size[1]) != w.size[1]) return false;
  for (int d = 0; d < 2; ++d) {
    if (geometry.strides.size() != 2 || geometry.strides[d] != geometry.kernel_size[d]) return false;
    if (static_cast<std::size_t>(w.size[2 + d]) != geometry.kernel_size[d]) return false;
    if (geometry.pads_begin.size() != 2 || geometry.pads_begin[d] != 0 || geometry.pads_end[d] != 0)
      return false;
    if (geometry.dilations.size() == 2 && geometry.dilations[d] != 1) return false;
    if (geometry.adjust_pads.size() == 2 && geometry.adjust_pads[d] != 0) return false;
  }
  return true;
}

bool TransposedConvolutionLayer::supportBackend(int backend_id) {
  return backend_id == cv::dnn::DNN_BACKEND_OPENCV;
}

bool TransposedConvolutionLayer::getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs,
                                                 int /*required_outputs*/,
                                                 std::vector<cv::dnn::MatShape>& outputs,
                                                 std::vector<cv::dnn::MatShape>& /*internals*/) const {
  CV_Assert(inputs.size() == 1 && inputs[0].size() == 4 && inputs[0][1] == in_channels_);
  outputs.assign(
      1, cv::dnn::MatShape{inputs[0][0], out_channels_, inputs[0][2] * kernel_h_, inputs[0][3] * kernel_w_});
  return false;
}

bool TransposedConvolutionLayer::setActivation(const cv::Ptr<cv::dnn::ActivationLayer>& layer) {
  activation_ = layer;
  return !activation_.empty();
}

void TransposedConvolutionLayer::forward(cv::InputArrayOfArrays inputs_arr,
                                         cv::OutputArrayOfArrays outputs_arr,
                                         cv::OutputArrayOfArrays /*internals*/) {
  LayerBlobs blobs = blobs_of(inputs_arr, outputs_arr);
  const cv::Mat& in = blobs.in;
  cv::Mat& out = blobs.out;
  CV_Assert(in.size[1] == in_channels_);
  const int batch = in.size[0], h = in.size[2], w = in.size[3];
  const int out_w = w * kernel_w_;
  const std::size_t in_plane = static_cast<std::size_t>(h) * w;
  const std::size_t out_plane = in_plane * kernel_h_ * kernel_w_;
  const std::size_t taps = static_cast<std::size_t>(kernel_h_) * kernel_w_;
  const float* src = in.ptr<float>();
  float* dst = out.ptr<float>();
  // One task per (image, output channel, input row): output row y * kh + a, column x * kw + b is
  // bias + sum_c in[c][y][x] * w[c][k][a][b]; summed per b over whole rows (vectorized), then
  // interleaved.
  cv::parallel_for_(cv::Range(0, batch * out_channels_ * h), [&](const cv::Range& r) {
    std::vector<float> sums(static_cast<std::size_t>(kernel_w_) * w);
    for (int task = r.start; task < r.end; ++task) {
      const int y = task % h, k = (task / h) % out_channels_, n = task / (h * out_channels_);
      const float* image = src + static_cast<std::size_t>(n) * in_channels_ * in_plane;
      float* plane = dst + (static_cast<std::size_t>(n) * out_channels_ + k) * out_plane;
      for (int a = 0; a < kernel_h_; ++a) {
        std::fill(sums.begin(), sums.end(), bias_[static_cast<std::size_t>(k)]);
        for (int c = 0; c < in_channels_; ++c) {
          const float* __restrict row = image + c * in_plane + static_cast<std::size_t>(y) * w;
          const float* wk =
              weights_.data() + (static_cast<std::size_t>(c) * out_channels_ + k) * taps + a * kernel_w_;
          for (int b = 0; b < kernel_w_; ++b) {
            float* __restrict s = sums.data() + static_cast<std::size_t>(b) * w;
            const float wb = wk[b];
            for (int x = 0; x < w; ++x) s[x] += wb * row[x];
          }
        }
        float* o = plane + static_cast<std::size_t>(y * kernel_h_ + a) * out_w;
        for (int x = 0; x < w; ++x)
          for (int b = 0; b < kernel_w_; ++b)
            o[x * kernel_w_ + b] = sums[static_cast<std::size_t>(b) * w + x];
      }
      // The activation on this task's rows, still in cache (forwardSlice takes any run of a plane).
      if (activation_) {
        float* rows = plane + static_cast<std::size_t>(y) * kernel_h_ * out_w;
        activation_->forwardSlice(rows, rows, kernel_h_ * out_w, out_plane, k, k + 1);
      }
    }
  });
}

}  // namespace lrd::segmentation
