// Segmentation presets (bench/results/segmenters.md): each preset's pre/post-processing, the
// `segmentation.preset` config key, the default segmenter per kind of data, and the MediaPipe
// selfie models converted by our own tools/tflite2onnx reproducing the reference masks in ../shared
// (skipped without it, or before scripts/fetch-models.sh has converted them).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "error_of.h"
#include "lrd/config/config.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/segmentation/onnx_presets.h"
#include "lrd/segmentation/onnx_segmenter.h"
#include "lrd/segmentation/segmentation_params.h"
#include "mask_iou.h"
#include "shared_dir.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using lrd::segmentation::Backend;
using lrd::segmentation::onnx_preset;
using lrd::segmentation::OnnxSegmenter;
using lrd::segmentation::OutputLayout;
using lrd::test::error_of;

using lrd::test::shared_dir;

namespace {

const char* const kPhotos[] = {"hyuto_sample.png", "mrcnn_ex01.jpg", "mrcnn_ex02.jpg",
                               "mrcnn_ex03.jpg",   "pphs_1.jpg",     "pphs_2.png",
                               "pphs_3.png",       "pphs_4.jpg",     "street.jpg"};

// The converted model of a selfie preset, or "" when it has not been converted yet.
fs::path converted(const std::string& preset) {
  try {
    return onnx_preset(preset).model;
  } catch (const lrd::Error&) {
    return {};
  }
}

#define REQUIRE_SHARED_AND_CONVERTED(preset)                                                    \
  do {                                                                                          \
    if (!fs::is_directory(shared_dir() / "data" / "people"))                                    \
      GTEST_SKIP() << "shared photos not found at " << shared_dir() << " (set LRD_SHARED_DIR)"; \
    if (converted(preset).empty())                                                              \
      GTEST_SKIP() << preset << " model not converted yet: run scripts/fetch-models.sh";        \
  } while (0)

using lrd::test::mask_iou;

}  // namespace

TEST(OnnxPresets, EachPresetCarriesItsModelsContract) {
  const auto fnet = onnx_preset("fnet");
  EXPECT_EQ(fnet.input_width, 160);
  EXPECT_EQ(fnet.input_height, 120);
  EXPECT_EQ(fnet.output, OutputLayout::Logits);
  EXPECT_EQ(fnet.classes.size(), 21u);
  EXPECT_EQ(fnet.dynamic_ids, (std::vector<int>{15, 3, 8, 10, 12, 13, 17}));
  EXPECT_EQ(fnet.model.filename(), "fnet-lite.onnx");
  EXPECT_TRUE(fs::is_regular_file(fnet.model)) << fnet.model;  // shipped in models/

  const auto espnet = onnx_preset("espnetv2-voc", "/models/espnet.onnx");
  EXPECT_EQ(espnet.model, fs::path("/models/espnet.onnx"));
  EXPECT_EQ(espnet.input_width, 384);
  EXPECT_EQ(espnet.input_height, 288);
  EXPECT_DOUBLE_EQ(espnet.mean[0], 0.485);
  EXPECT_DOUBLE_EQ(espnet.std[2], 0.225);
  EXPECT_TRUE(espnet.input_rgb);
  EXPECT_EQ(espnet.dynamic_ids, fnet.dynamic_ids);

  const auto selfie = onnx_preset("selfie", "/m/selfie.onnx");
  EXPECT_EQ(selfie.input_width, 256);
  EXPECT_EQ(selfie.input_height, 256);
  EXPECT_EQ(selfie.output, OutputLayout::Probability);
  EXPECT_DOUBLE_EQ(selfie.threshold, 0.5);
  EXPECT_DOUBLE_EQ(selfie.mean[0], 0.0);
  EXPECT_DOUBLE_EQ(selfie.std[0], 1.0);
  const auto landscape = onnx_preset("selfie-landscape", "/m/landscape.onnx");
  EXPECT_EQ(landscape.input_width, 256);
  EXPECT_EQ(landscape.input_height, 144);
  EXPECT_EQ(landscape.output, OutputLayout::Probability);
}

TEST(OnnxPresets, UnknownNameAndMissingModelsAreClearErrors) {
  std::string msg = error_of([] { (void)onnx_preset("selfy"); });
  EXPECT_NE(msg.find("selfy"), std::string::npos) << msg;
  EXPECT_NE(msg.find("selfie-landscape"), std::string::npos) << msg;
  msg = error_of([] { (void)onnx_preset("espnetv2-voc"); });
  EXPECT_NE(msg.find("model file"), std::string::npos) << msg;
  if (converted("selfie").empty()) {
    msg = error_of([] { (void)onnx_preset("selfie"); });
    EXPECT_NE(msg.find("selfie_segmentation.onnx"), std::string::npos) << msg;
    EXPECT_NE(msg.find("scripts/fetch-models.sh"), std::string::npos) << msg;
  }
}

TEST(OnnxPresets, ConfigPresetKeySetsTheBackendAndDefaults) {
  lrd::test::TempDir tmp("presets");
  const fs::path file = tmp.write("c.yaml",
                                  "segmentation:\n  preset: selfie-landscape\n  onnx:\n    model: /m/l.onnx\n"
                                  "    threshold: 0.7\n    own_kernels: false\n");
  const auto cfg = lrd::config::load_config(file);
  const auto s = lrd::segmentation::SegmentationParams::from_config(cfg.segmentation, file.parent_path());
  EXPECT_EQ(s.backend, Backend::Onnx);
  EXPECT_EQ(s.onnx.model, fs::path("/m/l.onnx"));
  EXPECT_EQ(s.onnx.input_height, 144);
  EXPECT_EQ(s.onnx.output, OutputLayout::Probability);
  EXPECT_DOUBLE_EQ(s.onnx.threshold, 0.7);  // the section's keys override the preset
  EXPECT_FALSE(s.onnx.own_kernels);
  EXPECT_EQ(s.onnx.dynamic_ids, (std::vector<int>{0}));

  const fs::path bad = tmp.write("bad.yaml", "segmentation:\n  preset: selfy\n");
  const auto bad_cfg = lrd::config::load_config(bad);
  const std::string msg =
      error_of([&] { (void)lrd::segmentation::SegmentationParams::from_config(bad_cfg.segmentation); });
  EXPECT_NE(msg.find("bad.yaml:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("selfy"), std::string::npos) << msg;
}

TEST(OnnxPresets, DefaultSegmenterIsFnetForSyntheticAndSelfieLandscapeForRealData) {
  lrd::test::TempDir tmp("default_seg");
  EXPECT_EQ(lrd::runner::default_segmenter(tmp.path()), "selfie-landscape");  // a TUM folder
  std::ofstream(tmp.path() / "sequence.json") << "{}";
  EXPECT_EQ(lrd::runner::default_segmenter(tmp.path()), "fnet");
}

TEST(ConvertedSelfie, ReproducesTheReferenceMasksOnThePhotos) {
  REQUIRE_SHARED_AND_CONVERTED("selfie");
  OnnxSegmenter seg(onnx_preset("selfie"));
  for (const char* name : kPhotos) {
    SCOPED_TRACE(name);
    const cv::Mat img = cv::imread((shared_dir() / "data/people" / name).string(), cv::IMREAD_COLOR);
    const cv::Mat ref = cv::imread(
        (shared_dir() / "data/people/ref_masks/selfie_256x256" / (fs::path(name).stem().string() + ".png"))
            .string(),
        cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(img.empty());
    ASSERT_FALSE(ref.empty());
    const cv::Mat mask = seg.segment(img, false, 0.0);
    ASSERT_EQ(mask.size(), ref.size());
    EXPECT_GE(mask_iou(mask != 0, ref != 0), 0.98);
  }
}

TEST(ConvertedSelfie, LandscapeOutputEqualsTheReferenceConversion) {
  REQUIRE_SHARED_AND_CONVERTED("selfie-landscape");
  const fs::path reference =
      shared_dir() / "models/mediapipe_selfie/selfie_segmentation_landscape_256x144.onnx";
  if (!fs::is_regular_file(reference)) GTEST_SKIP() << "no reference model at " << reference;
  OnnxSegmenter ours(onnx_preset("selfie-landscape"));
  OnnxSegmenter theirs(onnx_preset("selfie-landscape", reference));
  for (const char* name : {"mrcnn_ex01.jpg", "pphs_3.png", "street.jpg"}) {
    SCOPED_TRACE(name);
    const cv::Mat img = cv::imread((shared_dir() / "data/people" / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    const cv::Mat a = ours.forward(img, false), b = theirs.forward(img, false);
    ASSERT_EQ(a.dims, 4);
    ASSERT_EQ(a.size[2], 144);
    ASSERT_EQ(a.size[3], 256);
    ASSERT_EQ(a.total(), b.total());
    EXPECT_LT(cv::norm(a.reshape(1, 1), b.reshape(1, 1), cv::NORM_INF), 1e-3);
    EXPECT_GE(mask_iou(ours.segment(img, false, 0.0), theirs.segment(img, false, 0.0)), 0.98);
  }
}

// Our kernels (segmentation.onnx.own_kernels, on by default) change the speed of the
// selfie models, not their output: the same network output as OpenCV's layers alone, to the float
// rounding of sums taken in another order through some 50 layers, and the same masks.
TEST(ConvertedSelfie, OwnKernelsGiveOpenCvsOutput) {
  for (const char* preset : {"selfie", "selfie-landscape"}) {
    SCOPED_TRACE(preset);
    REQUIRE_SHARED_AND_CONVERTED(preset);
    auto params = onnx_preset(preset);
    ASSERT_TRUE(params.own_kernels);
    OnnxSegmenter ours(params);
    params.own_kernels = false;
    OnnxSegmenter opencv(params);
    for (const char* name : kPhotos) {
      SCOPED_TRACE(name);
      const cv::Mat img = cv::imread((shared_dir() / "data/people" / name).string(), cv::IMREAD_COLOR);
      ASSERT_FALSE(img.empty());
      const cv::Mat a = ours.forward(img, false), b = opencv.forward(img, false);
      ASSERT_EQ(a.total(), b.total());
      EXPECT_LT(cv::norm(a.reshape(1, 1), b.reshape(1, 1), cv::NORM_INF), 5e-4);
      const cv::Mat mask_ours = ours.segment(img, false, 0.0), mask_opencv = opencv.segment(img, false, 0.0);
      // Only a pixel whose probability is within rounding of the threshold may differ.
      EXPECT_LE(cv::countNonZero(mask_ours != mask_opencv), 10);
    }
  }
}
