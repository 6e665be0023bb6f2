// Our kernels (lrd/segmentation/own_kernels.h) against OpenCV's own layers on the same parameters
// and input: every geometry a kernel claims (kernel sizes, strides, pads, dilations, batches, a fused
// activation) must give OpenCV's output to float rounding, and what it does not claim stays OpenCV's.
#include <gtest/gtest.h>

#include <opencv2/dnn.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lrd/segmentation/own_kernels.h"

namespace {

using lrd::segmentation::OwnKernelsScope;

struct Geometry {
  int channels, kh, kw, sh, sw, dh, dw, pt, pl, pb, pr;  // channels: the groups' count
  int weights_per_group = 1;  // output channels per group (2: a depth multiplier, not depthwise)
  int in_per_group = 1;       // input channels per group (1: depthwise)
};

cv::dnn::LayerParams conv_params(const Geometry& g, bool bias) {
  cv::dnn::LayerParams p;
  p.name = "conv";
  p.type = "Convolution";
  p.set("kernel_h", g.kh);
  p.set("kernel_w", g.kw);
  p.set("stride_h", g.sh);
  p.set("stride_w", g.sw);
  p.set("dilation_h", g.dh);
  p.set("dilation_w", g.dw);
  p.set("pad_t", g.pt);
  p.set("pad_l", g.pl);
  p.set("pad_b", g.pb);
  p.set("pad_r", g.pr);
  p.set("group", g.channels);
  const int outputs = g.channels * g.weights_per_group;
  p.set("num_output", outputs);
  // As OpenCV's ONNX importer: the bias is a second blob, "bias_term" is not set.
  if (!bias) p.set("bias_term", false);
  cv::RNG rng(7);
  cv::Mat w(std::vector<int>{outputs, g.in_per_group, g.kh, g.kw}, CV_32F);
  rng.fill(w, cv::RNG::UNIFORM, -1.0, 1.0);
  p.blobs.push_back(w);
  if (bias) {
    cv::Mat b(1, outputs, CV_32F);
    rng.fill(b, cv::RNG::UNIFORM, -1.0, 1.0);
    p.blobs.push_back(b);
  }
  return p;
}

struct Result {
  cv::Mat out;
  std::string type;
};

// A chain of layers (type, parameters) on `input`, read inside an OwnKernelsScope with `own`:
// the output and the type of the layer the first one became.
Result run_net(const std::vector<std::pair<std::string, cv::dnn::LayerParams>>& layers, const cv::Mat& input,
               bool own) {
  std::optional<OwnKernelsScope> scope;
  if (own) scope.emplace();
  cv::dnn::Net net;
  int first = -1;
  for (std::size_t i = 0; i < layers.size(); ++i) {
    cv::dnn::LayerParams p = layers[i].second;
    p.type = layers[i].first;
    p.name = "layer" + std::to_string(i);
    const int id = net.addLayerToPrev(p.name, p.type, p);
    if (i == 0) first = id;
  }
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.setInput(input);
  Result res;
  res.out = net.forward().clone();
  res.type = net.getLayer(first)->type;
  return res;
}

Result run_layer(const std::string& type, const cv::dnn::LayerParams& params, const cv::Mat& input,
                 bool own) {
  return run_net({{type, params}}, input, own);
}

// One convolution (and optionally a ReLU after it, which OpenCV fuses into it).
Result run(const Geometry& g, bool bias, bool relu, const cv::Mat& input, bool own) {
  if (relu) return run_net({{"Convolution", conv_params(g, bias)}, {"ReLU", {}}}, input, own);
  return run_layer("Convolution", conv_params(g, bias), input, own);
}

cv::Mat random_input(int n, int c, int h, int w) {
  cv::Mat x(std::vector<int>{n, c, h, w}, CV_32F);
  cv::RNG(3).fill(x, cv::RNG::UNIFORM, -2.0, 2.0);
  return x;
}

double max_abs_diff(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a.reshape(1, 1), b.reshape(1, 1), cv::NORM_INF);
}

TEST(OwnKernels, GroupedConvolutionMatchesOpenCvOnEveryGeometryItTakes) {
  const Geometry cases[] = {
      // OpenCV 4.6's convolution takes symmetric pads only (its ONNX importer puts a Padding
      // layer before a convolution with uneven ones, as for selfie's stride-2 5x5).
      {16, 5, 5, 1, 1, 1, 1, 2, 2, 2, 2},  // selfie's 5x5 "same"
      {12, 5, 5, 2, 2, 1, 1, 0, 0, 0, 0},  // its stride-2 5x5 after the Padding layer
      {8, 7, 7, 1, 1, 2, 2, 6, 6, 6, 6},   // dilated
      {8, 3, 5, 1, 2, 1, 1, 1, 2, 1, 2},   // rectangular, stride in x only, different pads per axis
      {4, 5, 5, 3, 3, 1, 1, 0, 0, 0, 0},   // stride 3, no pads
      {6, 1, 7, 1, 1, 1, 1, 0, 3, 0, 3},   // a 1x7 row filter
  };
  for (const Geometry& g : cases) {
    for (const bool bias : {false, true}) {
      for (const bool relu : {false, true}) {
        SCOPED_TRACE(::testing::Message() << g.kh << "x" << g.kw << " stride " << g.sh << "," << g.sw
                                          << " dilation " << g.dh << " bias " << bias << " relu " << relu);
        const cv::Mat x = random_input(2, g.channels, 13, 18);
        const Result ours = run(g, bias, relu, x, true);
        const Result theirs = run(g, bias, relu, x, false);
        EXPECT_EQ(ours.type, "GroupedConvolution");
        EXPECT_EQ(theirs.type, "Convolution");
        ASSERT_EQ(ours.out.dims, 4);
        for (int d = 0; d < 4; ++d) ASSERT_EQ(ours.out.size[d], theirs.out.size[d]) << "dimension " << d;
        EXPECT_LT(max_abs_diff(ours.out, theirs.out), 1e-4);
        if (relu) {
          double lowest = 0;
          cv::minMaxLoc(ours.out.reshape(1, 1), &lowest);
          EXPECT_GE(lowest, 0.0);  // the fused activation ran
        }
      }
    }
  }
}

TEST(OwnKernels, GroupedConvolutionWithFewInputChannelsMatchesOpenCv) {
  // Taken on CPUs with AVX2 and FMA (OpenCV's GEMM path is faster than ours without them).
  const bool avx2 = cv::checkHardwareSupport(CV_CPU_AVX2) && cv::checkHardwareSupport(CV_CPU_FMA3);
  const Geometry cases[] = {
      {1, 3, 3, 2, 2, 1, 1, 1, 1, 1, 1, 16, 3},  // a first layer on RGB (selfie's: 3 -> 16, stride 2)
      {1, 5, 5, 1, 1, 1, 1, 2, 2, 2, 2, 8, 4},   // 4 input channels, 5x5
      {2, 3, 3, 1, 1, 1, 1, 1, 1, 1, 1, 4, 2},   // two groups of 2 -> 4
      {1, 3, 5, 1, 2, 2, 2, 2, 4, 2, 4, 4, 1},   // one input channel, dilated, stride in x only
  };
  for (const Geometry& g : cases) {
    for (const bool relu : {false, true}) {
      SCOPED_TRACE(::testing::Message()
                   << g.channels << " groups of " << g.in_per_group << " -> " << g.weights_per_group << ", "
                   << g.kh << "x" << g.kw << " relu " << relu);
      const cv::Mat x = random_input(2, g.channels * g.in_per_group, 13, 18);
      const Result ours = run(g, true, relu, x, true);
      const Result theirs = run(g, true, relu, x, false);
      EXPECT_EQ(ours.type, avx2 ? "GroupedConvolution" : "Convolution");
      ASSERT_EQ(ours.out.dims, 4);
      for (int d = 0; d < 4; ++d) ASSERT_EQ(ours.out.size[d], theirs.out.size[d]) << "dimension " << d;
      EXPECT_LT(max_abs_diff(ours.out, theirs.out), 1e-4);
    }
  }
}

TEST(OwnKernels, GroupedConvolutionLeavesTheRestToOpenCv) {
  const cv::Mat x = random_input(1, 8, 9, 9);
  // OpenCV's own 3x3 depthwise path is fast; a depth multiplier of 2 is neither depthwise nor in
  // fours; 1x1 kernels are OpenCV's GEMM; 8 input channels per group are more than a few.
  for (const Geometry& g :
       {Geometry{8, 3, 3, 1, 1, 1, 1, 1, 1, 1, 1}, Geometry{8, 5, 5, 1, 1, 1, 1, 2, 2, 2, 2, 2},
        Geometry{2, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 4, 4}, Geometry{1, 3, 3, 1, 1, 1, 1, 1, 1, 1, 1, 8, 8}}) {
    const Result r = run(g, true, false, x, true);
    EXPECT_EQ(r.type, "Convolution");
  }
  // Outside a scope every convolution is OpenCV's, also after a scope has registered ours.
  EXPECT_EQ(run(Geometry{8, 5, 5, 1, 1, 1, 1, 2, 2, 2, 2}, true, false, x, false).type, "Convolution");
}

// A transposed convolution with kernel == stride (selfie's last layer: 16 channels to 1 at x2),
// with and without the sigmoid after it (which OpenCV fuses into it).
Result run_transposed(int in_c, int out_c, int kh, int kw, bool sigmoid, const cv::Mat& input, bool own) {
  cv::dnn::LayerParams p;
  p.set("kernel_h", kh);
  p.set("kernel_w", kw);
  p.set("stride_h", kh);
  p.set("stride_w", kw);
  p.set("num_output", out_c);
  cv::RNG rng(11);
  cv::Mat w(std::vector<int>{in_c, out_c, kh, kw}, CV_32F), b(1, out_c, CV_32F);
  rng.fill(w, cv::RNG::UNIFORM, -1.0, 1.0);
  rng.fill(b, cv::RNG::UNIFORM, -1.0, 1.0);
  p.blobs = {w, b};
  if (sigmoid) return run_net({{"Deconvolution", p}, {"Sigmoid", {}}}, input, own);
  return run_layer("Deconvolution", p, input, own);
}

TEST(OwnKernels, TransposedConvolutionMatchesOpenCv) {
  struct Case {
    int in_c, out_c, kh, kw;
  };
  for (const Case& c : {Case{16, 1, 2, 2}, Case{4, 3, 2, 3}, Case{5, 2, 4, 4}}) {
    for (const bool sigmoid : {false, true}) {
      SCOPED_TRACE(::testing::Message()
                   << c.in_c << "->" << c.out_c << " " << c.kh << "x" << c.kw << " sigmoid " << sigmoid);
      const cv::Mat x = random_input(2, c.in_c, 7, 11);
      const Result ours = run_transposed(c.in_c, c.out_c, c.kh, c.kw, sigmoid, x, true);
      const Result theirs = run_transposed(c.in_c, c.out_c, c.kh, c.kw, sigmoid, x, false);
      EXPECT_EQ(ours.type, "TransposedConvolution");
      EXPECT_EQ(theirs.type, "Deconvolution");
      ASSERT_EQ(ours.out.total(), theirs.out.total());
      for (int d = 0; d < 4; ++d) ASSERT_EQ(ours.out.size[d], theirs.out.size[d]) << "dimension " << d;
      EXPECT_LT(max_abs_diff(ours.out, theirs.out), 1e-4);
    }
  }
}

TEST(OwnKernels, SigmoidMatchesOpenCv) {
  // 3 x 70 x 90 values: several of its 16384-value tasks and a partial one; -30..30 reaches both tails.
  cv::Mat x(std::vector<int>{1, 3, 70, 90}, CV_32F);
  cv::RNG(5).fill(x, cv::RNG::UNIFORM, -30.0, 30.0);
  const Result ours = run_layer("Sigmoid", {}, x, true), theirs = run_layer("Sigmoid", {}, x, false);
  EXPECT_EQ(ours.type, "OwnSigmoid");
  EXPECT_EQ(theirs.type, "Sigmoid");
  EXPECT_LT(max_abs_diff(ours.out, theirs.out), 1e-6);
}

TEST(OwnKernels, LinearResizeMatchesOpenCv) {
  // As OpenCV's ONNX importer describes Resize(linear, half_pixel) to a fixed size; x2 takes our
  // kernel, other sizes cv::resize per plane as OpenCV's layer does.
  for (const auto& [h, w] : {std::pair{14, 18}, std::pair{10, 13}, std::pair{7, 9}}) {
    SCOPED_TRACE(::testing::Message() << "to " << h << "x" << w);
    cv::dnn::LayerParams p;
    p.set("interpolation", "opencv_linear");
    p.set("align_corners", false);
    p.set("height", h);
    p.set("width", w);
    const cv::Mat x = random_input(2, 5, 7, 9);
    const Result ours = run_layer("Resize", p, x, true), theirs = run_layer("Resize", p, x, false);
    EXPECT_EQ(ours.type, "LinearResize");
    EXPECT_EQ(theirs.type, "Resize");
    ASSERT_EQ(ours.out.total(), theirs.out.total());
    for (int d = 0; d < 4; ++d) ASSERT_EQ(ours.out.size[d], theirs.out.size[d]) << "dimension " << d;
    EXPECT_LT(max_abs_diff(ours.out, theirs.out), 1e-5);
  }
  cv::dnn::LayerParams nearest;
  nearest.set("interpolation", "nearest");
  nearest.set("height", 14);
  nearest.set("width", 18);
  EXPECT_EQ(run_layer("Resize", nearest, random_input(1, 2, 7, 9), true).type, "Resize");
}

TEST(OwnKernels, GlobalAveragePoolingMatchesOpenCv) {
  cv::dnn::LayerParams p;
  p.set("global_pooling", true);
  p.set("pool", "AVE");
  // Small (summed on the calling thread) and large (in parallel) inputs.
  for (const cv::Mat& x : {random_input(2, 6, 9, 11), random_input(1, 8, 100, 100)}) {
    const Result ours = run_layer("Pooling", p, x, true), theirs = run_layer("Pooling", p, x, false);
    EXPECT_EQ(ours.type, "GlobalAveragePooling");
    ASSERT_EQ(ours.out.total(), theirs.out.total());
    for (int d = 0; d < 4; ++d) ASSERT_EQ(ours.out.size[d], theirs.out.size[d]) << "dimension " << d;
    EXPECT_LT(max_abs_diff(ours.out, theirs.out), 1e-5);
  }
  cv::dnn::LayerParams max_pool;
  max_pool.set("global_pooling", true);
  max_pool.set("pool", "MAX");
  EXPECT_EQ(run_layer("Pooling", max_pool, random_input(1, 2, 5, 5), true).type, "Pooling");
}

TEST(OwnKernels, HardSwishMatchesOpenCv) {
  // -5..5 spans both clamps; 3 x 70 x 90 values: several tasks and a partial vector at the end.
  cv::Mat x(std::vector<int>{1, 3, 70, 91}, CV_32F);
  cv::RNG(9).fill(x, cv::RNG::UNIFORM, -5.0, 5.0);
  const Result ours = run_layer("HardSwish", {}, x, true), theirs = run_layer("HardSwish", {}, x, false);
  EXPECT_EQ(ours.type, "OwnHardSwish");
  EXPECT_EQ(theirs.type, "HardSwish");
  EXPECT_EQ(max_abs_diff(ours.out, theirs.out), 0.0);  // the same arithmetic
}

TEST(OwnKernels, ZeroPaddingMatchesOpenCv) {
  // As OpenCV's ONNX importer writes the pads of a convolution with uneven ones: (before, after)
  // per axis, N and C untouched. Small (one thread) and large (in parallel) tensors.
  for (const cv::Mat& x : {random_input(2, 3, 9, 11), random_input(1, 16, 72, 128)}) {
    for (const std::vector<int>& pads :
         {std::vector<int>{0, 0, 0, 0, 0, 1, 0, 1}, {0, 0, 0, 0, 1, 2, 1, 2}, {0, 0, 0, 0, 3, 0, 0, 2}}) {
      cv::dnn::LayerParams p;
      p.set("paddings", cv::dnn::DictValue::arrayInt(pads.data(), static_cast<int>(pads.size())));
      const Result ours = run_layer("Padding", p, x, true), theirs = run_layer("Padding", p, x, false);
      EXPECT_EQ(ours.type, "ZeroPadding");
      EXPECT_EQ(theirs.type, "Padding");
      ASSERT_EQ(ours.out.total(), theirs.out.total());
      for (int d = 0; d < 4; ++d) ASSERT_EQ(ours.out.size[d], theirs.out.size[d]) << "dimension " << d;
      EXPECT_EQ(max_abs_diff(ours.out, theirs.out), 0.0);
    }
  }
  cv::dnn::LayerParams reflect;
  const int pads[] = {0, 0, 0, 0, 1, 1, 1, 1};
  reflect.set("paddings", cv::dnn::DictValue::arrayInt(pads, 8));
  reflect.set("type", "reflect");
  EXPECT_EQ(run_layer("Padding", reflect, random_input(1, 2, 5, 5), true).type, "Padding");
}

}  // namespace
