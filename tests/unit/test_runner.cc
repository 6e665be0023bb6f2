// Camera resolution of `lrdslam run` (runner::resolve_config): explicit flags first, then the
// config, the sequence's own settings.yaml and the TUM folder name.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "lrd/runner/sequence_runner.h"
#include "lrd/util/error.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using lrd::runner::resolve_config;
using lrd::runner::RunOptions;

TEST(ResolveConfig, FreiburgFolderNamePicksTheTumPreset) {
  lrd::test::TempDir tmp("runner_settings");
  const fs::path seq = tmp.path() / "rgbd_dataset_freiburg1_xyz";
  fs::create_directories(seq);
  RunOptions o;
  o.sequence = seq;
  std::string source;
  const auto cfg = resolve_config(o, &source);
  EXPECT_DOUBLE_EQ(cfg.camera.fx, lrd::camera::camera_preset("tum1").fx);
  EXPECT_NE(source.find("tum1"), std::string::npos) << source;
  o.sequence = seq.string() + "/";  // a trailing slash changes nothing
  EXPECT_DOUBLE_EQ(resolve_config(o).camera.fx, lrd::camera::camera_preset("tum1").fx);
}

TEST(ResolveConfig, SequenceSettingsThenPresetThenDefault) {
  lrd::test::TempDir tmp("runner_folder");
  const fs::path seq = tmp.path() / "my_sequence";
  fs::create_directories(seq);
  RunOptions o;
  o.sequence = seq;
  EXPECT_DOUBLE_EQ(resolve_config(o).camera.fx, lrd::camera::camera_preset("tum3").fx);  // default
  tmp.write("my_sequence/settings.yaml",
            "%YAML:1.0\nCamera.fx: 500.0\nCamera.fy: 501.0\nCamera.cx: 320.0\nCamera.cy: 240.0\n"
            "Camera.bf: 40.0\nThDepth: 40.0\nDepthMapFactor: 5000.0\n");
  EXPECT_DOUBLE_EQ(resolve_config(o).camera.fx, 500.0);
  o.preset = "tum2";
  EXPECT_DOUBLE_EQ(resolve_config(o).camera.fx, lrd::camera::camera_preset("tum2").fx);
  o.settings = seq / "settings.yaml";
  EXPECT_THROW((void)resolve_config(o), lrd::Error);  // both given
}

TEST(ResolveConfig, RunOnAMissingFolderFailsWithItsName) {
  RunOptions o;
  o.sequence = "/nonexistent/sequence";
  o.out = "/tmp/lrd_runner_test_out";
  try {
    (void)lrd::runner::run_sequence(o);
    FAIL() << "no error";
  } catch (const lrd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/sequence"), std::string::npos) << e.what();
  }
}

}  // namespace
