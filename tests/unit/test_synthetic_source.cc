// The streamed synthetic source (`lrdslam run --synth`; the long runs of bench/results/scale.md):
// its frames are the frames `lrdslam synth` writes, read back; its ground truth is
// groundtruth.txt's; a run over it gets the synthetic camera and, in a semantic mode, the network
// trained on the renders.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "lrd/io/tum_sequence.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/synth/sequence_writer.h"
#include "lrd/synth/synthetic_source.h"
#include "temp_dir.h"

namespace lrd {
namespace {

synth::SynthOptions walking(int frames) {
  synth::SynthOptions o;
  o.preset = "walking_xyz";
  o.seed = 7;
  o.frames = frames;
  return o;
}

TEST(SyntheticSource, FramesEqualTheWrittenSequenceReadBack) {
  const synth::SyntheticSource source(walking(3));
  test::TempDir dir("synthetic_source");
  (void)synth::write_sequence(source.sequence(), dir.path());
  const io::TumSequence written = io::TumSequence::open(dir.path());
  ASSERT_EQ(source.size(), written.size());
  for (std::size_t i = 0; i < source.size(); ++i) {
    EXPECT_EQ(source.entry(i).rgb_path.filename(), written.entry(i).rgb_path.filename());
    EXPECT_EQ(source.entry(i).depth_path.filename(), written.entry(i).depth_path.filename());
    EXPECT_DOUBLE_EQ(source.entry(i).timestamp, written.entry(i).timestamp);
    const io::RgbdFrame a = source.load_rgbd(i, 1.0);  // the factor is a file's: ignored
    const io::RgbdFrame b = written.load_rgbd(i, 5000.0);
    EXPECT_EQ(cv::norm(a.rgb, b.rgb, cv::NORM_INF), 0.0) << "frame " << i;
    ASSERT_EQ(a.depth.type(), CV_32FC1);
    EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0) << "frame " << i;
    EXPECT_GT(cv::countNonZero(a.depth), a.depth.total() / 2);
  }
  const io::Trajectory gt = *source.ground_truth(), gt_file = *written.ground_truth();
  ASSERT_EQ(gt.size(), gt_file.size());
  for (std::size_t i = 0; i < gt.size(); ++i) {
    EXPECT_NEAR(gt[i].timestamp, gt_file[i].timestamp, 1e-6);
    EXPECT_LT((gt[i].pose.translation() - gt_file[i].pose.translation()).norm(), 1e-4);
  }
  EXPECT_EQ(source.path().string(), "synth:walking_xyz?seed=7&session=1&frames=3");
  EXPECT_FALSE(source.folder());
  EXPECT_THROW((void)source.load_rgbd(3, 1.0), Error);
}

TEST(SyntheticSource, ARunGetsTheSyntheticCameraAndInSemanticModesFnet) {
  runner::RunOptions o;
  o.source = std::make_shared<const synth::SyntheticSource>(walking(2));
  o.mode = "full";
  std::string from;
  const config::Config cfg = runner::resolve_config(o, &from);
  EXPECT_NE(from.find("synthetic camera"), std::string::npos) << from;
  const camera::PinholeCamera tum3 = camera::camera_preset("tum3");
  EXPECT_EQ(cfg.camera.fx, tum3.fx);
  EXPECT_EQ(cfg.camera.cy, tum3.cy);
  EXPECT_EQ(cfg.camera.bf, tum3.bf);
  EXPECT_EQ(cfg.camera.depth_map_factor, tum3.depth_map_factor);
  const SystemParams params = runner::configure_system(o, cfg);
  EXPECT_EQ(params.segmentation.backend, segmentation::Backend::Onnx);
  EXPECT_NE(params.segmentation.onnx.model.filename().string().find("fnet"), std::string::npos)
      << params.segmentation.onnx.model;
}

TEST(SyntheticSource, ATumRunGetsTheCalibratedCameraWithItsRollingShutter) {
  synth::SynthOptions tum = walking(1);
  tum.realism = synth::realism_profile("tum");
  runner::RunOptions o;
  o.source = std::make_shared<const synth::SyntheticSource>(tum);
  const config::Config cfg = runner::resolve_config(o, nullptr);
  EXPECT_DOUBLE_EQ(cfg.camera.readout_time, tum.realism.readout_time);  // the tracker compensates it
  EXPECT_NEAR(cfg.camera.fx, camera::camera_preset("tum3").fx * (1.0 + tum.realism.focal_error_x), 1e-9);
  o.source = std::make_shared<const synth::SyntheticSource>(walking(1));
  EXPECT_EQ(runner::resolve_config(o, nullptr).camera.readout_time, 0.0);  // clean: a global shutter
}

TEST(SyntheticSource, AnUnknownPresetIsAnError) {
  synth::SynthOptions o = walking(2);
  o.preset = "no_such_preset";
  EXPECT_THROW(synth::SyntheticSource{o}, Error);
}

}  // namespace
}  // namespace lrd
