// The shipped FNet-lite model (models/fnet-lite.onnx) through our `onnx` backend, on synthetic
// frames it never saw: its training data come from seeds >= 1000 (`lrdslam synth --export-voc`),
// these from the benchmark's evaluation seed 1. Bar (models/fnet-lite.md): person IoU >= 0.8.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>

#include "lrd/runner/sequence_runner.h"
#include "lrd/segmentation/onnx_segmenter.h"
#include "lrd/synth/synthetic_sequence.h"

namespace {

namespace fs = std::filesystem;

const fs::path kModel = fs::path(LRD_SOURCE_DIR) / "models" / "fnet-lite.onnx";

// Exactly the `--segmenter fnet` preset's settings, with the model of this source tree.
lrd::segmentation::OnnxParams fnet_params() {
  lrd::segmentation::SegmentationParams p =
      lrd::runner::segmenter_preset("fnet", {}, lrd::segmentation::SegmentationParams{});
  p.onnx.model = kModel;
  return p.onnx;
}

// `frames` frames of a synthetic preset, seed 1.
lrd::synth::SyntheticSequence rendered(const char* preset, int frames) {
  lrd::synth::SynthOptions o;
  o.preset = preset;
  o.seed = 1;
  o.frames = frames;
  return lrd::synth::SyntheticSequence(o);
}

TEST(FnetModel, PersonIouOnHeldOutSyntheticFrames) {
  if (!fs::exists(kModel)) GTEST_SKIP() << kModel << " has not shipped yet";
  lrd::segmentation::OnnxSegmenter net(fnet_params());

  std::size_t intersection = 0, union_ = 0, dynamic_hits = 0, dynamic_truth = 0;
  for (const char* preset : {"walking_xyz", "sitting_halfsphere", "walking_pushed"}) {
    const lrd::synth::SyntheticSequence seq = rendered(preset, 200);
    for (int i = 10; i < seq.size(); i += 40) {
      const lrd::synth::SynthFrame f = seq.render(i);
      const cv::Mat labels = net.labels(f.rgb, /*rgb_order=*/false);
      const cv::Mat mask = net.segment(f.rgb, false, f.timestamp);
      ASSERT_EQ(labels.size(), f.rgb.size());
      for (int v = 0; v < labels.rows; ++v)
        for (int u = 0; u < labels.cols; ++u) {
          const bool predicted = labels.at<std::uint8_t>(v, u) == 15;  // VOC person
          const bool truth = f.voc_class.at<std::uint8_t>(v, u) == 15;
          intersection += predicted && truth;
          union_ += predicted || truth;
          dynamic_truth += truth;
          dynamic_hits += truth && mask.at<std::uint8_t>(v, u) != 0;
        }
    }
  }
  ASSERT_GT(union_, 0u);
  const double iou = static_cast<double>(intersection) / static_cast<double>(union_);
  std::printf("[   info   ] held-out person IoU %.3f, people covered by the dynamic mask %.3f\n", iou,
              static_cast<double>(dynamic_hits) / static_cast<double>(dynamic_truth));
  EXPECT_GE(iou, 0.8) << "person IoU " << iou;
  // The dynamic mask the tracker gets covers the people.
  EXPECT_GE(static_cast<double>(dynamic_hits) / static_cast<double>(dynamic_truth), 0.8);
}

// segment() takes a shortcut to the dynamic mask (best dynamic minus best static logit at the
// network's resolution, interpolated): it must agree with the arg-max labels it stands in for.
TEST(FnetModel, DynamicMaskAgreesWithTheLabels) {
  if (!fs::exists(kModel)) GTEST_SKIP() << kModel << " has not shipped yet";
  const lrd::segmentation::OnnxParams params = fnet_params();
  lrd::segmentation::OnnxSegmenter net(params);
  const lrd::synth::SyntheticSequence seq = rendered("walking_xyz", 120);
  std::size_t differ = 0, total = 0, person = 0;
  for (int i = 0; i < seq.size(); i += 30) {
    const lrd::synth::SynthFrame f = seq.render(i);
    const cv::Mat labels = net.labels(f.rgb, false);
    const cv::Mat mask = net.segment(f.rgb, false, f.timestamp);
    ASSERT_EQ(mask.size(), f.rgb.size());
    ASSERT_EQ(mask.type(), CV_8UC1);
    EXPECT_EQ(cv::countNonZero((mask != 0) & (mask != 255)), 0);
    cv::Mat dynamic = cv::Mat::zeros(labels.size(), CV_8UC1);
    for (const int id : params.dynamic_ids) dynamic |= labels == id;
    differ += static_cast<std::size_t>(cv::countNonZero(dynamic != mask));
    person += static_cast<std::size_t>(cv::countNonZero(dynamic));
    total += labels.total();
  }
  ASSERT_GT(person, total / 100);  // people are in view
  // Only outline pixels may differ (two interpolations of the same decision).
  EXPECT_LT(static_cast<double>(differ), 0.05 * static_cast<double>(person)) << differ << " of " << person;
}

// Our kernels (segmentation.onnx.own_kernels) are on for fnet too; today it has none of the layers
// they take (its up-samplings are nearest), and whatever a retrained model gains, its logits must
// stay OpenCV's.
TEST(FnetModel, OwnKernelsGiveOpenCvsLogits) {
  if (!fs::exists(kModel)) GTEST_SKIP() << kModel << " has not shipped yet";
  lrd::segmentation::OnnxParams params = fnet_params();
  ASSERT_TRUE(params.own_kernels);
  lrd::segmentation::OnnxSegmenter ours(params);
  params.own_kernels = false;
  lrd::segmentation::OnnxSegmenter opencv(params);
  const lrd::synth::SyntheticSequence seq = rendered("walking_xyz", 60);
  for (int i = 0; i < seq.size(); i += 30) {
    const lrd::synth::SynthFrame f = seq.render(i);
    const cv::Mat a = ours.forward(f.rgb, false), b = opencv.forward(f.rgb, false);
    ASSERT_EQ(a.total(), b.total());
    EXPECT_LT(cv::norm(a.reshape(1, 1), b.reshape(1, 1), cv::NORM_INF), 1e-3);
  }
}

}  // namespace
