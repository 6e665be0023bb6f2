// Camera resolution of `lrdslam run` (runner::resolve_config): explicit flags first, then the
// config, the sequence's own settings.yaml and the TUM folder name.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "lrd/runner/sequence_runner.h"
#include "lrd/util/error.h"
#include "temp_dir.h"

namespace {

namespace fs = std::filesystem;
using lrd::runner::resolve_config;
using lrd::runner::RunOptions;

// Options for `lrdslam run --sequence` on an empty folder of that name under `tmp`.
RunOptions sequence_folder(const lrd::test::TempDir& tmp, const std::string& name) {
  RunOptions o;
  o.sequence = tmp.path() / name;
  fs::create_directories(o.sequence);
  return o;
}

TEST(ResolveConfig, FreiburgFolderNamePicksTheTumPreset) {
  lrd::test::TempDir tmp("runner_settings");
  RunOptions o = sequence_folder(tmp, "rgbd_dataset_freiburg1_xyz");
  const fs::path seq = o.sequence;
  std::string source;
  const auto cfg = resolve_config(o, &source);
  EXPECT_DOUBLE_EQ(cfg.camera.fx, lrd::camera::camera_preset("tum1").fx);
  EXPECT_NE(source.find("tum1"), std::string::npos) << source;
  o.sequence = seq.string() + "/";  // a trailing slash changes nothing
  EXPECT_DOUBLE_EQ(resolve_config(o).camera.fx, lrd::camera::camera_preset("tum1").fx);
}

TEST(ResolveConfig, BonnFolderNamePicksTheBonnPreset) {
  lrd::test::TempDir tmp("runner_bonn");
  RunOptions o = sequence_folder(tmp, "rgbd_bonn_crowd");
  std::string source;
  const auto cfg = resolve_config(o, &source);
  // Bonn RGB-D Dynamic's published calibration (one camera for every sequence).
  EXPECT_DOUBLE_EQ(cfg.camera.fx, 542.822841);
  EXPECT_DOUBLE_EQ(cfg.camera.cy, 237.756098);
  EXPECT_DOUBLE_EQ(cfg.camera.distortion.k1, 0.039903);
  EXPECT_DOUBLE_EQ(cfg.camera.depth_map_factor, 5000.0);
  EXPECT_EQ(source, "preset bonn (from the folder name)");
  // Only the dataset's own prefix: a folder that merely mentions bonn keeps the default.
  EXPECT_DOUBLE_EQ(resolve_config(sequence_folder(tmp, "my_bonn_run")).camera.fx,
                   lrd::camera::camera_preset("tum3").fx);
  o.preset = "tum1";  // the flag wins over the name
  EXPECT_DOUBLE_EQ(resolve_config(o).camera.fx, lrd::camera::camera_preset("tum1").fx);
}

TEST(ResolveConfig, SequenceSettingsThenPresetThenDefault) {
  lrd::test::TempDir tmp("runner_folder");
  RunOptions o = sequence_folder(tmp, "my_sequence");
  const fs::path seq = o.sequence;
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

namespace {
// A source that carries a camera (as a bag's camera_info), named like a file.
class CameraSource final : public lrd::io::FrameSource {
 public:
  explicit CameraSource(fs::path path) : path_(std::move(path)) {}
  std::size_t size() const override { return 0; }
  const lrd::io::FrameEntry& entry(std::size_t) const override { return entry_; }
  lrd::io::RgbdFrame load_rgbd(std::size_t, double) const override { return {}; }
  std::string describe(std::size_t) const override { return path_.string(); }
  fs::path path() const override { return path_; }
  std::optional<fs::path> folder() const override { return std::nullopt; }
  std::optional<lrd::io::Trajectory> ground_truth() const override { return std::nullopt; }
  std::string ground_truth_origin() const override { return ""; }
  std::optional<lrd::io::SourceCamera> camera() const override {
    lrd::io::SourceCamera c;
    c.width = 320;
    c.height = 240;
    c.fx = c.fy = 262.5;
    c.cx = 159.5;
    c.cy = 119.5;
    c.k1 = 0.1;
    c.origin = "camera_info in " + path_.string();
    return c;
  }

 private:
  fs::path path_;
  lrd::io::FrameEntry entry_;
};
}  // namespace

TEST(ResolveConfig, ACarriedCameraComesAfterTheCommandLineAndTumBagsUseTheirSensorsCalibration) {
  RunOptions o;
  o.source = std::make_shared<CameraSource>("/data/robot_run.bag");
  std::string source;
  auto cfg = resolve_config(o, &source);
  EXPECT_EQ(cfg.camera.fx, 262.5);
  EXPECT_EQ(cfg.camera.width, 320);
  EXPECT_EQ(cfg.camera.distortion.k1, 0.1);
  EXPECT_EQ(cfg.camera.depth_map_factor, lrd::camera::PinholeCamera{}.depth_map_factor);
  EXPECT_EQ(source, "camera_info in /data/robot_run.bag");
  o.preset = "tum1";
  EXPECT_DOUBLE_EQ(resolve_config(o).camera.fx, lrd::camera::camera_preset("tum1").fx);
  // TUM's own bags carry the driver's default camera_info: the sensor's calibration wins.
  o.preset.reset();
  o.source = std::make_shared<CameraSource>("/data/rgbd_dataset_freiburg2_xyz.bag");
  cfg = resolve_config(o, &source);
  EXPECT_DOUBLE_EQ(cfg.camera.fx, lrd::camera::camera_preset("tum2").fx);
  EXPECT_NE(source.find("preset tum2 (from the bag name"), std::string::npos) << source;
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
