// The `onnx` segmentation backend with real pretrained models (shared/models): ESPNetv2 on Pascal
// VOC (logits) and MediaPipe selfie segmentation (probability), compared with the reference masks
// under shared/data/people/ref_masks; models whose output does not fit the config, and missing
// files. Skipped when the shared folder is absent.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "error_of.h"
#include "lrd/segmentation/onnx_presets.h"
#include "lrd/segmentation/onnx_segmenter.h"
#include "lrd/segmentation/segmentation_params.h"
#include "lrd/util/error.h"
#include "mask_iou.h"
#include "shared_dir.h"

namespace fs = std::filesystem;
using lrd::segmentation::OnnxParams;
using lrd::segmentation::OnnxSegmenter;
using lrd::segmentation::OutputLayout;

using lrd::test::shared_dir;

namespace {

// Skips the test unless the shared models and photos are there.
#define REQUIRE_SHARED()                                                                                   \
  do {                                                                                                     \
    if (!fs::is_directory(shared_dir() / "models") || !fs::is_directory(shared_dir() / "data" / "people")) \
      GTEST_SKIP() << "shared folder with models and photos not found at " << shared_dir()                 \
                   << " (set LRD_SHARED_DIR)";                                                             \
  } while (0)

fs::path espnet_model() {
  return shared_dir() / "models/espnetv2_voc/espnetv2_s2.0_voc_384x288.onnx";
}
fs::path selfie_model() {
  return shared_dir() / "models/mediapipe_selfie/selfie_segmentation_256x256.onnx";
}

// Through the espnetv2-voc preset: the preset's pre-processing is what the reference used.
OnnxParams espnet_params() {
  return lrd::segmentation::onnx_preset("espnetv2-voc", espnet_model());
}

OnnxParams selfie_params() {
  OnnxParams p;
  p.model = selfie_model();
  p.input_width = 256;
  p.input_height = 256;
  p.scale = 1.0 / 255.0;
  p.mean = {0.0, 0.0, 0.0};
  p.std = {1.0, 1.0, 1.0};
  p.input_rgb = true;
  p.output = OutputLayout::Probability;
  p.threshold = 0.5;
  p.dynamic_ids = {0};
  return p;
}

// The networks load once per process (ESPNetv2 s2.0 takes about half a second per forward pass,
// one of which the constructor's check spends).
OnnxSegmenter& espnet() {
  static OnnxSegmenter seg(espnet_params());
  return seg;
}
OnnxSegmenter& selfie() {
  static OnnxSegmenter seg(selfie_params());
  return seg;
}

cv::Mat photo(const std::string& name) {
  const fs::path file = shared_dir() / "data/people" / name;
  cv::Mat img = cv::imread(file.string(), cv::IMREAD_COLOR);  // BGR; an alpha channel is dropped
  EXPECT_FALSE(img.empty()) << file;
  return img;
}

cv::Mat reference(const std::string& model, const std::string& photo_name) {
  const fs::path file =
      shared_dir() / "data/people/ref_masks" / model / (fs::path(photo_name).stem().string() + ".png");
  cv::Mat ref = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  EXPECT_FALSE(ref.empty()) << file;
  EXPECT_EQ(ref.type(), CV_8UC1) << file;
  return ref;
}

using lrd::test::error_of;

using lrd::test::mask_iou;

}  // namespace

TEST(OnnxSegmenter, EspnetVocLabelsMatchTheReference) {
  REQUIRE_SHARED();
  OnnxSegmenter& seg = espnet();
  EXPECT_NE(seg.describe().find("espnetv2_s2.0_voc_384x288.onnx"), std::string::npos) << seg.describe();
  // Five of the nine photos, covering person, horse, car and tvmonitor, a PNG with an alpha channel
  // and a 5-megapixel one (the s2.0 model takes 0.15-0.5 s a frame; ASan builds are slower still).
  for (const std::string name :
       {"hyuto_sample.png", "mrcnn_ex02.jpg", "mrcnn_ex03.jpg", "pphs_2.png", "street.jpg"}) {
    SCOPED_TRACE(name);
    const cv::Mat img = photo(name), ref = reference("espnetv2_s2.0_voc_384x288", name);
    const cv::Mat labels = seg.labels(img, false);
    ASSERT_EQ(labels.type(), CV_8UC1);
    ASSERT_EQ(labels.size(), img.size());
    ASSERT_EQ(ref.size(), img.size());
    const double agree =
        1.0 - static_cast<double>(cv::countNonZero(labels != ref)) / static_cast<double>(ref.total());
    EXPECT_GE(agree, 0.98);
    // The person class is found where the reference has it.
    EXPECT_GE(mask_iou(labels == 15, ref == 15), 0.95);
    double max_label = 0.0;
    cv::minMaxLoc(labels, nullptr, &max_label);
    EXPECT_LT(max_label, 21.0);
  }
}

TEST(OnnxSegmenter, EspnetMaskIsTheDynamicClasses) {
  REQUIRE_SHARED();
  OnnxSegmenter& seg = espnet();
  // Person (15) and horse (13) are dynamic, the cars (7) are not.
  const cv::Mat img = photo("mrcnn_ex02.jpg"), ref = reference("espnetv2_s2.0_voc_384x288", "mrcnn_ex02.jpg");
  ASSERT_GT(cv::countNonZero(ref == 7), 1000);
  ASSERT_GT(cv::countNonZero(ref == 13), 1000);
  ASSERT_GT(cv::countNonZero(ref == 15), 1000);
  // An RGB image with rgb_order = true gives what the BGR one gives with false.
  cv::Mat rgb;
  cv::cvtColor(img, rgb, cv::COLOR_BGR2RGB);
  const cv::Mat mask = seg.segment(rgb, true, 0.0);
  ASSERT_EQ(mask.type(), CV_8UC1);
  ASSERT_EQ(mask.size(), img.size());
  const cv::Mat expected = (ref == 13) | (ref == 15);
  EXPECT_GE(mask_iou(mask, expected), 0.95);
  EXPECT_LT(cv::countNonZero(mask & (ref == 7)), 0.02 * cv::countNonZero(ref == 7));
  EXPECT_EQ(cv::countNonZero((mask != 0) & (mask != 255)), 0);
}

TEST(OnnxSegmenter, SelfiePersonMaskMatchesTheReference) {
  REQUIRE_SHARED();
  OnnxSegmenter& seg = selfie();
  for (const std::string name : {"hyuto_sample.png", "mrcnn_ex01.jpg", "mrcnn_ex02.jpg", "mrcnn_ex03.jpg",
                                 "pphs_1.jpg", "pphs_2.png", "pphs_3.png", "pphs_4.jpg", "street.jpg"}) {
    SCOPED_TRACE(name);
    const cv::Mat img = photo(name), ref = reference("selfie_256x256", name);
    ASSERT_EQ(ref.size(), img.size());
    const cv::Mat labels = seg.labels(img, false);
    ASSERT_EQ(labels.type(), CV_8UC1);
    ASSERT_EQ(labels.size(), img.size());
    double max_label = 0.0;
    cv::minMaxLoc(labels, nullptr, &max_label);
    EXPECT_LE(max_label, 1.0);  // probability layout: 1 above the threshold, else 0
    EXPECT_GE(mask_iou(labels != 0, ref != 0), 0.98);
  }
}

TEST(OnnxSegmenter, SelfieSegmentGivesAFullMaskInEitherChannelOrder) {
  REQUIRE_SHARED();
  OnnxSegmenter& seg = selfie();
  const cv::Mat bgr = photo("pphs_4.jpg"), ref = reference("selfie_256x256", "pphs_4.jpg");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  const cv::Mat from_bgr = seg.segment(bgr, false, 1.0), from_rgb = seg.segment(rgb, true, 2.0);
  ASSERT_EQ(from_bgr.type(), CV_8UC1);
  EXPECT_EQ(cv::countNonZero(from_bgr != from_rgb), 0);  // the same blob either way
  EXPECT_EQ(cv::countNonZero((from_bgr != 0) & (from_bgr != 255)), 0);
  EXPECT_GE(mask_iou(from_bgr, ref), 0.98);
  EXPECT_GT(cv::countNonZero(from_bgr), static_cast<int>(0.05 * static_cast<double>(from_bgr.total())));
  // Passing the wrong order changes the input (red and blue swapped), so the result may differ,
  // but a grey image is accepted and segmented at its own size.
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  const cv::Mat from_grey = seg.segment(grey, true, 3.0);
  EXPECT_EQ(from_grey.size(), grey.size());
  EXPECT_EQ(from_grey.type(), CV_8UC1);
  // The raw output is 1 x 1 x 256 x 256 probabilities in [0, 1].
  const cv::Mat out = seg.forward(bgr, false);
  ASSERT_EQ(out.dims, 4);
  EXPECT_EQ(out.size[0], 1);
  EXPECT_EQ(out.size[1], 1);
  EXPECT_EQ(out.size[2], 256);
  EXPECT_EQ(out.size[3], 256);
  double lo = 0.0, hi = 0.0;
  cv::minMaxIdx(out, &lo, &hi);
  EXPECT_GE(lo, 0.0);
  EXPECT_LE(hi, 1.0);
  EXPECT_GT(hi, 0.9);
}

TEST(OnnxSegmenter, OutputThatDoesNotFitTheConfigIsRefused) {
  REQUIRE_SHARED();
  OnnxParams p = selfie_params();
  p.output = OutputLayout::Logits;
  p.classes = lrd::segmentation::voc_classes();
  p.dynamic_ids = {15};
  const std::string msg = error_of([&] { OnnxSegmenter s(p); });
  EXPECT_NE(msg.find(selfie_model().string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("1x1x256x256"), std::string::npos) << msg;  // what the model gives
  EXPECT_NE(msg.find("1x21xHxW"), std::string::npos) << msg;     // what the config expects

  // The VOC model's 21-channel logits are not a probability map either.
  OnnxParams q = espnet_params();
  q.output = OutputLayout::Probability;
  q.dynamic_ids = {0};
  const std::string msg2 = error_of([&] { OnnxSegmenter s(q); });
  EXPECT_NE(msg2.find(espnet_model().string()), std::string::npos) << msg2;
  EXPECT_NE(msg2.find("1x21x144x192"), std::string::npos) << msg2;
  EXPECT_NE(msg2.find("1x1xHxW"), std::string::npos) << msg2;
}

TEST(OnnxSegmenter, MissingOrBrokenModelFileIsAnErrorNamingIt) {
  const fs::path missing = fs::temp_directory_path() / "lrd_no_such_model_dir" / "net.onnx";
  OnnxParams p;
  p.model = missing;
  std::string msg = error_of([&] { OnnxSegmenter s(p); });
  EXPECT_NE(msg.find(missing.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("not found"), std::string::npos) << msg;

  p.model.clear();
  msg = error_of([&] { OnnxSegmenter s(p); });
  EXPECT_NE(msg.find("segmentation.onnx.model"), std::string::npos) << msg;

  // A file that is not an ONNX model.
  const fs::path junk =
      fs::temp_directory_path() / ("lrd_junk_model_" + std::to_string(::getpid()) + ".onnx");
  { std::ofstream(junk) << "definitely not protobuf"; }
  p.model = junk;
  msg = error_of([&] { OnnxSegmenter s(p); });
  std::error_code ec;
  fs::remove(junk, ec);
  EXPECT_NE(msg.find(junk.string()), std::string::npos) << msg;
}
