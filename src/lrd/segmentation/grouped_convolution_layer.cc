#include "lrd/segmentation/grouped_convolution_layer.h"

#include <algorithm>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/dnn/shape_utils.hpp>

#include "lrd/segmentation/layer_data.h"

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#define LRD_AVX2_KERNEL 1
#endif

namespace lrd::segmentation {

namespace {

// Each padded input plane is stored as stride_w column phases (phase p holds columns p, p + sw,
// p + 2 sw, ...), so that for every kernel tap a run of consecutive outputs reads consecutive
// floats, strided or not. An output row is then summed 8 outputs at a time in registers over all
// taps (input channels of the group x kernel rows x kernel columns): the first version looped over
// x once per tap, 4 vectors long on selfie's 16-wide maps, and spent more on the loops' set-up than
// on the work (2.7 GMAC/s; this is 4x that).
using Layout = GroupedConvolutionLayer::PlaneLayout;

void pad_plane(const Layout& g, const float* in, float* plane) {
  // Zeros only where no input lands: the rows above and below, and each row's ends.
  std::fill(plane, plane + g.pt * g.row_stride, 0.0f);
  std::fill(plane + (g.pt + g.in_h) * g.row_stride, plane + g.plane_size, 0.0f);
  for (int y = 0; y < g.in_h; ++y) {
    float* row = plane + (y + g.pt) * g.row_stride;
    const float* src = in + static_cast<std::size_t>(y) * g.in_w;
    if (g.sw == 1) {
      std::fill(row, row + g.pl, 0.0f);
      std::copy(src, src + g.in_w, row + g.pl);
      std::fill(row + g.pl + g.in_w, row + g.row_stride, 0.0f);
      continue;
    }
    std::fill(row, row + g.row_stride, 0.0f);
    // Column c = x + pl goes to phase c % sw, slot c / sw: phase by phase, a strided copy each.
    for (int phase = 0; phase < g.sw; ++phase) {
      int x = (phase - g.pl % g.sw + g.sw) % g.sw;  // first input column of this phase
      float* __restrict dst = row + phase * g.phase_len + (x + g.pl) / g.sw;
      const int n = x < g.in_w ? (g.in_w - x + g.sw - 1) / g.sw : 0;
      const float* __restrict s = src + x;
      for (int k = 0; k < n; ++k) dst[k] = s[k * g.sw];
    }
  }
}

// One output plane from its group's padded input planes (starting at `planes`).
void convolve(const Layout& g, const float* planes, const float* w, float bias, float* out) {
  const int taps = static_cast<int>(g.tap_at.size());
  const int* tap_at = g.tap_at.data();
  for (int y = 0; y < g.out_h; ++y) {
    const float* base = planes + static_cast<std::size_t>(y) * g.sh * g.row_stride;
    float* o = out + static_cast<std::size_t>(y) * g.out_w;
    int x = 0;
#if CV_SIMD128
    for (; x + 8 <= g.out_w; x += 8) {
      cv::v_float32x4 acc0 = cv::v_setall_f32(bias), acc1 = acc0;
      for (int t = 0; t < taps; ++t) {
        const float* p = base + tap_at[t] + x;
        const cv::v_float32x4 wt = cv::v_setall_f32(w[t]);
        acc0 = cv::v_muladd(cv::v_load(p), wt, acc0);
        acc1 = cv::v_muladd(cv::v_load(p + 4), wt, acc1);
      }
      cv::v_store(o + x, acc0);
      cv::v_store(o + x + 4, acc1);
    }
    for (; x + 4 <= g.out_w; x += 4) {
      cv::v_float32x4 acc = cv::v_setall_f32(bias);
      for (int t = 0; t < taps; ++t)
        acc = cv::v_muladd(cv::v_load(base + tap_at[t] + x), cv::v_setall_f32(w[t]), acc);
      cv::v_store(o + x, acc);
    }
#endif
    for (; x < g.out_w; ++x) {
      float acc = bias;
      for (int t = 0; t < taps; ++t) acc += w[t] * base[tap_at[t] + x];
      o[x] = acc;
    }
  }
}

#ifdef LRD_AVX2_KERNEL
// A convolution whose groups read few input channels and write many output ones (a first layer on
// RGB: 3 in, 16 out, 3x3, stride 2): output row y of 4 output channels at once, 8 outputs a time in
// AVX2 registers, so that each input vector loaded feeds 4 fused multiply-adds. `w4` holds the 4
// channels' weights tap by tap (taps x 4). Compiled for AVX2 + FMA whatever the baseline; called
// only where the CPU has them.
__attribute__((target("avx2,fma"))) void convolve_row_x4_avx2(const Layout& g, const float* planes,
                                                              const float* w4, const float* bias4,
                                                              float* const out[4], int y) {
  const int taps = static_cast<int>(g.tap_at.size());
  const int* tap_at = g.tap_at.data();
  const float* base = planes + static_cast<std::size_t>(y) * g.sh * g.row_stride;
  const std::size_t row = static_cast<std::size_t>(y) * g.out_w;
  int x = 0;
  for (; x + 8 <= g.out_w; x += 8) {
    __m256 a0 = _mm256_set1_ps(bias4[0]), a1 = _mm256_set1_ps(bias4[1]);
    __m256 a2 = _mm256_set1_ps(bias4[2]), a3 = _mm256_set1_ps(bias4[3]);
    for (int t = 0; t < taps; ++t) {
      const __m256 v = _mm256_loadu_ps(base + tap_at[t] + x);
      const float* wt = w4 + 4 * t;
      a0 = _mm256_fmadd_ps(v, _mm256_broadcast_ss(wt), a0);
      a1 = _mm256_fmadd_ps(v, _mm256_broadcast_ss(wt + 1), a1);
      a2 = _mm256_fmadd_ps(v, _mm256_broadcast_ss(wt + 2), a2);
      a3 = _mm256_fmadd_ps(v, _mm256_broadcast_ss(wt + 3), a3);
    }
    _mm256_storeu_ps(out[0] + row + x, a0);
    _mm256_storeu_ps(out[1] + row + x, a1);
    _mm256_storeu_ps(out[2] + row + x, a2);
    _mm256_storeu_ps(out[3] + row + x, a3);
  }
  for (; x < g.out_w; ++x)
    for (int kk = 0; kk < 4; ++kk) {
      float acc = bias4[kk];
      for (int t = 0; t < taps; ++t) acc += w4[4 * t + kk] * base[tap_at[t] + x];
      out[kk][row + x] = acc;
    }
}

bool cpu_has_avx2_fma() {
  static const bool has = cv::checkHardwareSupport(CV_CPU_AVX2) && cv::checkHardwareSupport(CV_CPU_FMA3);
  return has;
}
#else
bool cpu_has_avx2_fma() {
  return false;
}
#endif

int to_int(std::size_t v) {
  return static_cast<int>(v);
}

}  // namespace

GroupedConvolutionLayer::GroupedConvolutionLayer(const cv::dnn::LayerParams& params,
                                                 const cv::dnn::BaseConvolutionLayer& geometry)
    : cv::dnn::Layer(params) {
  // Not "Convolution": OpenCV's fusion code takes every layer of that type for its own class.
  type = "GroupedConvolution";
  const cv::Mat& w = params.blobs[0];
  out_channels_ = w.size[0];
  groups_ = params.get<int>("group", 1);
  in_channels_ = w.size[1] * groups_;
  kernel_h_ = to_int(geometry.kernel_size[0]);
  kernel_w_ = to_int(geometry.kernel_size[1]);
  stride_h_ = to_int(geometry.strides[0]);
  stride_w_ = to_int(geometry.strides[1]);
  dilation_h_ = to_int(geometry.dilations[0]);
  dilation_w_ = to_int(geometry.dilations[1]);
  pad_top_ = to_int(geometry.pads_begin[0]);
  pad_left_ = to_int(geometry.pads_begin[1]);
  pad_bottom_ = to_int(geometry.pads_end[0]);
  pad_right_ = to_int(geometry.pads_end[1]);
  weights_ = weights_of(params);
  bias_ = bias_of(params, out_channels_);
  if (w.size[1] > 1 || w.size[0] != groups_) {
    // Not depthwise: the AVX2 kernel's layout, output channels in fours interleaved per tap.
    const std::size_t taps = weights_.size() / static_cast<std::size_t>(out_channels_);
    weights_x4_.resize(weights_.size());
    for (int b = 0; b < out_channels_ / 4; ++b)
      for (std::size_t t = 0; t < taps; ++t)
        for (int kk = 0; kk < 4; ++kk)
          weights_x4_[(b * taps + t) * 4 + kk] = weights_[(static_cast<std::size_t>(b) * 4 + kk) * taps + t];
  }
}

bool GroupedConvolutionLayer::handles(const cv::dnn::LayerParams& params,
                                      const cv::dnn::BaseConvolutionLayer& geometry) {
  if (geometry.kernel_size.size() != 2 || !geometry.padMode.empty()) return false;
  if (geometry.strides.size() != 2 || geometry.dilations.size() != 2 || geometry.pads_begin.size() != 2 ||
      geometry.pads_end.size() != 2)
    return false;
  if (params.blobs.empty()) return false;  // weights given at run time
  const cv::Mat& w = params.blobs[0];
  if (w.dims != 4 || w.depth() != CV_32F) return false;
  if (w.size[2] != to_int(geometry.kernel_size[0]) || w.size[3] != to_int(geometry.kernel_size[1]))
    return false;
  const int groups = params.get<int>("group", 1);
  // Few input channels per group, output channels in fours: the AVX2 kernel (OpenCV's GEMM path is
  // faster than ours without it). 1x1 kernels stay OpenCV's, a GEMM is right for them.
  const bool depthwise = groups >= 2 && w.size[0] == groups && w.size[1] == 1;
  if (!depthwise)
    return w.size[1] <= 4 && (w.size[0] / groups) % 4 == 0 && w.size[2] * w.size[3] > 1 && cpu_has_avx2_fma();
  // OpenCV's own 3x3 depthwise path is fast: keep it.
  return !(geometry.kernel_size[0] == 3 && geometry.kernel_size[1] == 3);
}

bool GroupedConvolutionLayer::supportBackend(int backend_id) {
  return backend_id == cv::dnn::DNN_BACKEND_OPENCV;
}

bool GroupedConvolutionLayer::getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs,
                                              int /*required_outputs*/,
                                              std::vector<cv::dnn::MatShape>& outputs,
                                              std::vector<cv::dnn::MatShape>& /*internals*/) const {
  CV_Assert(inputs.size() == 1 && inputs[0].size() == 4 && inputs[0][1] == in_channels_);
  const int h = inputs[0][2] + pad_top_ + pad_bottom_ - dilation_h_ * (kernel_h_ - 1) - 1;
  const int w = inputs[0][3] + pad_left_ + pad_right_ - dilation_w_ * (kernel_w_ - 1) - 1;
  CV_Assert(h >= 0 && w >= 0);
  outputs.assign(1, cv::dnn::MatShape{inputs[0][0], out_channels_, h / stride_h_ + 1, w / stride_w_ + 1});
  return false;
}

bool GroupedConvolutionLayer::setActivation(const cv::Ptr<cv::dnn::ActivationLayer>& layer) {
  activation_ = layer;
  return !activation_.empty();
}

void GroupedConvolutionLayer::finalize(cv::InputArrayOfArrays inputs_arr,
                                       cv::OutputArrayOfArrays outputs_arr) {
  std::vector<cv::Mat> inputs, outputs;
  inputs_arr.getMatVector(inputs);
  outputs_arr.getMatVector(outputs);
  if (!inputs.empty() && !outputs.empty()) plan(cv::dnn::shape(inputs[0]), cv::dnn::shape(outputs[0]));
}

void GroupedConvolutionLayer::plan(const cv::dnn::MatShape& in, const cv::dnn::MatShape& out) {
  CV_Assert(in.size() == 4 && out.size() == 4);
  Layout g;
  g.in_h = in[2];
  g.in_w = in[3];
  g.out_h = out[2];
  g.out_w = out[3];
  g.sh = stride_h_, g.sw = stride_w_, g.pt = pad_top_, g.pl = pad_left_;
  const int padded_h =
      std::max(g.in_h + pad_top_ + pad_bottom_, (g.out_h - 1) * g.sh + (kernel_h_ - 1) * dilation_h_ + 1);
  const int padded_w =
      std::max(g.in_w + pad_left_ + pad_right_, (g.out_w - 1) * g.sw + (kernel_w_ - 1) * dilation_w_ + 1);
  g.phase_len = (padded_w + g.sw - 1) / g.sw;
  g.row_stride = static_cast<std::size_t>(g.sw) * g.phase_len;
  g.plane_size = padded_h * g.row_stride;
  for (int c = 0; c < in_channels_ / groups_; ++c)
    for (int i = 0; i < kernel_h_; ++i)
      for (int j = 0; j < kernel_w_; ++j) {
        const int column = j * dilation_w_;
        g.tap_at.push_back(to_int(c * g.plane_size) + (i * dilation_h_ * g.sw + column % g.sw) * g.phase_len +
                           column / g.sw);
      }
  layout_ = std::move(g);
  padded_.resize(static_cast<std::size_t>(in[0]) * in_channels_ * layout_.plane_size);
}

void GroupedConvolutionLayer::forward(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr,
                                      cv::OutputArrayOfArrays /*internals*/) {
  LayerBlobs blobs = blobs_of(inputs_arr, outputs_arr);
  const cv::Mat& in = blobs.in;
  cv::Mat& out = blobs.out;
  CV_Assert(in.size[1] == in_channels_);
  if (in.size[2] != layout_.in_h || in.size[3] != layout_.in_w ||
      in.size[0] * in_channels_ * layout_.plane_size != padded_.size())
    plan(cv::dnn::shape(in), cv::dnn::shape(out));  // not finalized for these shapes
  const Layout& g = layout_;
  const int in_per_group = in_channels_ / groups_, out_per_group = out_channels_ / groups_;
  const int batch = in.size[0];
  const std::size_t in_plane = static_cast<std::size_t>(g.in_h) * g.in_w;
  const std::size_t out_plane = static_cast<std::size_t>(g.out_h) * g.out_w;
  const float* src = in.ptr<float>();
  float* dst = out.ptr<float>();
  const std::size_t taps = g.tap_at.size();
  if (in_per_group == 1 && out_per_group == 1) {
    // Depthwise: each task pads the one plane its output channel reads, then sums it.
    cv::parallel_for_(cv::Range(0, batch * out_channels_), [&](const cv::Range& r) {
      for (int p = r.start; p < r.end; ++p) {
        const int k = p % out_channels_;
        float* planes = padded_.data() + static_cast<std::size_t>(p) * g.plane_size;
        pad_plane(g, src + p * in_plane, planes);
        float* o = dst + p * out_plane;
        convolve(g, planes, weights_.data() + k * taps, bias_[static_cast<std::size_t>(k)], o);
        if (activation_) activation_->forwardSlice(o, o, to_int(out_plane), out_plane, k, k + 1);
      }
    });
    return;
  }
#ifdef LRD_AVX2_KERNEL
  // Few input channels per group (handles() took it only with AVX2): all planes padded first, then
  // tasks of (image, 4 output channels, output row).
  cv::parallel_for_(cv::Range(0, batch * in_channels_), [&](const cv::Range& r) {
    for (int p = r.start; p < r.end; ++p) pad_plane(g, src + p * in_plane, padded_.data() + p * g.plane_size);
  });
  const int blocks = out_channels_ / 4;
  cv::parallel_for_(cv::Range(0, batch * blocks * g.out_h), [&](const cv::Range& r) {
    for (int task = r.start; task < r.end; ++task) {
      const int y = task % g.out_h, b = (task / g.out_h) % blocks, n = task / (g.out_h * blocks);
      const int k = 4 * b;
      const std::size_t first_plane =
          static_cast<std::size_t>(n) * in_channels_ + (k / out_per_group) * in_per_group;
      float* const first_out = dst + (static_cast<std::size_t>(n) * out_channels_ + k) * out_plane;
      float* const out4[4] = {first_out, first_out + out_plane, first_out + 2 * out_plane,
                              first_out + 3 * out_plane};
      convolve_row_x4_avx2(g, padded_.data() + first_plane * g.plane_size, weights_x4_.data() + b * taps * 4,
                           bias_.data() + k, out4, y);
      if (activation_)
        for (int kk = 0; kk < 4; ++kk) {
          float* o = out4[kk] + static_cast<std::size_t>(y) * g.out_w;
          activation_->forwardSlice(o, o, g.out_w, out_plane, k + kk, k + kk + 1);
        }
    }
  });
#else
  CV_Error(cv::Error::StsNotImplemented, "GroupedConvolutionLayer: only depthwise without AVX2");
#endif
}

}  // namespace lrd::segmentation
