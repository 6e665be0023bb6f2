// lrd::config::read_orbslam_settings: ORB-SLAM2 and ORB-SLAM3 v1.0 files read unchanged.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <utility>

#include "lrd/config/orbslam_settings.h"
#include "lrd/util/error.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using lrd::config::read_orbslam_settings;

namespace {

class SettingsTest : public ::testing::Test {
 protected:
  fs::path write(const std::string& name, const std::string& text) const { return tmp_.write(name, text); }

  // The message of the lrd::Error that f throws.
  template <class F>
  static std::string error_of(F f) {
    try {
      f();
    } catch (const lrd::Error& e) {
      return e.what();
    }
    ADD_FAILURE() << "expected lrd::Error";
    return {};
  }

  lrd::test::TempDir tmp_{"settings"};
  const fs::path dir_ = tmp_.path();
};

// As ORB-SLAM2's Examples/RGB-D/TUM1.yaml (with its Viewer keys, which are ignored).
const char* const kOrbSlam2 = R"(%YAML:1.0

# Camera calibration and distortion parameters (OpenCV)
Camera.fx: 517.306408
Camera.fy: 516.469215
Camera.cx: 318.643040
Camera.cy: 255.313989

Camera.k1: 0.262383
Camera.k2: -0.953104
Camera.p1: -0.005358
Camera.p2: 0.002628
Camera.k3: 1.163314

Camera.width: 640
Camera.height: 480
Camera.fps: 30.0
Camera.bf: 40.0
Camera.RGB: 0
ThDepth: 40.0
DepthMapFactor: 5000.0

ORBextractor.nFeatures: 1500
ORBextractor.scaleFactor: 1.2
ORBextractor.nLevels: 8
ORBextractor.iniThFAST: 20
ORBextractor.minThFAST: 7

Viewer.KeyFrameSize: 0.05
Viewer.ViewpointF: 500
)";

// As ORB-SLAM3 v1.0's Examples/RGB-D/TUM2.yaml.
const char* const kOrbSlam3 = R"(%YAML:1.0

File.version: "1.0"
Camera.type: "PinHole"

Camera1.fx: 520.908620
Camera1.fy: 521.007327
Camera1.cx: 325.141442
Camera1.cy: 249.701764

Camera1.k1: 0.231222
Camera1.k2: -0.784899
Camera1.p1: -0.003257
Camera1.p2: -0.000105
Camera1.k3: 0.917205

Camera.width: 640
Camera.height: 480
Camera.fps: 30
Camera.RGB: 1

Stereo.ThDepth: 40.0
Stereo.b: 0.07732

RGBD.DepthMapFactor: 5208.0

ORBextractor.nFeatures: 1000
ORBextractor.scaleFactor: 1.2
ORBextractor.nLevels: 8
ORBextractor.iniThFAST: 20
ORBextractor.minThFAST: 7
)";

std::string without_line(std::string text, const std::string& key) {
  const auto pos = text.find(key);
  return text.erase(pos, text.find('\n', pos) - pos + 1);
}

}  // namespace

TEST_F(SettingsTest, ReadsOrbSlam2File) {
  const auto s = read_orbslam_settings(write("TUM1.yaml", kOrbSlam2));
  EXPECT_EQ(s.camera.name, "TUM1");
  EXPECT_DOUBLE_EQ(s.camera.fx, 517.306408);
  EXPECT_DOUBLE_EQ(s.camera.fy, 516.469215);
  EXPECT_DOUBLE_EQ(s.camera.cx, 318.643040);
  EXPECT_DOUBLE_EQ(s.camera.cy, 255.313989);
  EXPECT_DOUBLE_EQ(s.camera.distortion.k1, 0.262383);
  EXPECT_DOUBLE_EQ(s.camera.distortion.k2, -0.953104);
  EXPECT_DOUBLE_EQ(s.camera.distortion.p1, -0.005358);
  EXPECT_DOUBLE_EQ(s.camera.distortion.p2, 0.002628);
  EXPECT_DOUBLE_EQ(s.camera.distortion.k3, 1.163314);
  EXPECT_EQ(s.camera.width, 640);
  EXPECT_EQ(s.camera.height, 480);
  EXPECT_DOUBLE_EQ(s.camera.fps, 30.0);
  EXPECT_DOUBLE_EQ(s.camera.bf, 40.0);
  EXPECT_FALSE(s.camera.rgb_order);
  EXPECT_DOUBLE_EQ(s.camera.th_depth, 40.0);
  EXPECT_DOUBLE_EQ(s.camera.depth_map_factor, 5000.0);
  EXPECT_EQ(s.orb.n_features, 1500);
  EXPECT_FLOAT_EQ(s.orb.scale_factor, 1.2f);
  EXPECT_EQ(s.orb.n_levels, 8);
  EXPECT_EQ(s.orb.ini_th_fast, 20);
  EXPECT_EQ(s.orb.min_th_fast, 7);
}

TEST_F(SettingsTest, ReadsOrbSlam3File) {
  const auto s = read_orbslam_settings(write("TUM2.yaml", kOrbSlam3));
  EXPECT_DOUBLE_EQ(s.camera.fx, 520.908620);
  EXPECT_DOUBLE_EQ(s.camera.cy, 249.701764);
  EXPECT_DOUBLE_EQ(s.camera.distortion.p2, -0.000105);
  EXPECT_DOUBLE_EQ(s.camera.distortion.k3, 0.917205);
  EXPECT_EQ(s.camera.width, 640);
  EXPECT_DOUBLE_EQ(s.camera.fps, 30.0);
  EXPECT_TRUE(s.camera.rgb_order);
  EXPECT_DOUBLE_EQ(s.camera.bf, 0.07732 * 520.908620);  // bf = b * fx
  EXPECT_DOUBLE_EQ(s.camera.th_depth, 40.0);
  EXPECT_DOUBLE_EQ(s.camera.depth_map_factor, 5208.0);
  EXPECT_EQ(s.orb.n_features, 1000);
}

TEST_F(SettingsTest, MissingRequiredKeyNamesFileAndKey) {
  const auto f = write("nofx.yaml", without_line(kOrbSlam2, "Camera.fx:"));
  const std::string msg = error_of([&] { (void)read_orbslam_settings(f); });
  EXPECT_NE(msg.find(f.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing required key 'Camera.fx'"), std::string::npos) << msg;

  const auto g = write("nodmf.yaml", without_line(kOrbSlam3, "RGBD.DepthMapFactor:"));
  const std::string msg3 = error_of([&] { (void)read_orbslam_settings(g); });
  EXPECT_NE(msg3.find("nodmf.yaml"), std::string::npos) << msg3;
  EXPECT_NE(msg3.find("RGBD.DepthMapFactor"), std::string::npos) << msg3;
}

TEST_F(SettingsTest, OptionalKeysDefault) {
  // ORB-SLAM2 files without distortion, size or ORB keys are common.
  const auto f = write("min.yaml",
                       "%YAML:1.0\nCamera.fx: 500\nCamera.fy: 500\nCamera.cx: 320\nCamera.cy: 240\n"
                       "Camera.bf: 40\nThDepth: 35\nDepthMapFactor: 1000\n");
  const auto s = read_orbslam_settings(f);
  EXPECT_DOUBLE_EQ(s.camera.fx, 500.0);
  EXPECT_TRUE(s.camera.distortion.is_zero());
  EXPECT_EQ(s.camera.width, 640);
  EXPECT_DOUBLE_EQ(s.camera.th_depth, 35.0);
  EXPECT_DOUBLE_EQ(s.camera.depth_map_factor, 1000.0);
  EXPECT_EQ(s.orb.n_features, 1000);
  EXPECT_EQ(s.camera.readout_time, 0.0);  // a global shutter
}

TEST_F(SettingsTest, RollingShutterReadoutTime) {
  const std::string base =
      "%YAML:1.0\nCamera.fx: 500\nCamera.fy: 500\nCamera.cx: 320\nCamera.cy: 240\n"
      "Camera.bf: 40\nThDepth: 35\nDepthMapFactor: 1000\nCamera.fps: 30\n";
  EXPECT_DOUBLE_EQ(
      read_orbslam_settings(write("rs.yaml", base + "Camera.readoutTime: 0.028\n")).camera.readout_time,
      0.028);
  // Longer than a frame period, or negative: one line naming the file and the key.
  for (const char* bad : {"0.04", "-0.01"}) {
    const auto f = write("rs_bad.yaml", base + "Camera.readoutTime: " + bad + "\n");
    const std::string msg = error_of([&] { (void)read_orbslam_settings(f); });
    EXPECT_NE(msg.find("rs_bad.yaml"), std::string::npos) << msg;
    EXPECT_NE(msg.find("Camera.readoutTime"), std::string::npos) << msg;
    EXPECT_NE(msg.find("must be in [0, 1/fps]"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

TEST_F(SettingsTest, BadInputIsOneLineError) {
  const auto missing = dir_ / "nope.yaml";
  std::string msg = error_of([&] { (void)read_orbslam_settings(missing); });
  EXPECT_NE(msg.find("nope.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not found"), std::string::npos) << msg;

  const auto garbage = write("bad.yaml", "%YAML:1.0\nCamera.fx: 1\n  Camera.fy: : 2\n");
  msg = error_of([&] { (void)read_orbslam_settings(garbage); });
  EXPECT_NE(msg.find(garbage.string() + ":3: cannot parse settings file"), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  const auto binary = write("bin.yaml", std::string("\x01\x02\xff\xfe", 4) + "\t: [\n");
  msg = error_of([&] { (void)read_orbslam_settings(binary); });
  EXPECT_NE(msg.find(binary.string() + ":"), std::string::npos) << msg;
  EXPECT_NE(msg.find("cannot parse settings file"), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;

  const auto wrong = write("wrong.yaml", "%YAML:1.0\nCamera.fx: fast\n");
  msg = error_of([&] { (void)read_orbslam_settings(wrong); });
  EXPECT_NE(msg.find("wrong.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'Camera.fx' must be a number"), std::string::npos) << msg;

  std::string kb = kOrbSlam3;
  kb.replace(kb.find("PinHole"), 7, "KannalaBrandt8");
  const auto fisheye = write("kb.yaml", kb);
  msg = error_of([&] { (void)read_orbslam_settings(fisheye); });
  EXPECT_NE(msg.find("Camera.type"), std::string::npos) << msg;
  EXPECT_NE(msg.find("KannalaBrandt8"), std::string::npos) << msg;
}

TEST_F(SettingsTest, ShippedSettingsFilesMatchPresets) {
  const std::pair<const char*, const char*> shipped[] = {
      {"TUM1.yaml", "tum1"}, {"TUM2.yaml", "tum2"}, {"TUM3.yaml", "tum3"}, {"Bonn.yaml", "bonn"}};
  for (const auto& [file, n] : shipped) {
    const auto s = read_orbslam_settings(fs::path(LRD_SOURCE_DIR) / "config" / file);
    const auto p = lrd::camera::camera_preset(n);
    EXPECT_DOUBLE_EQ(s.camera.fx, p.fx) << n;
    EXPECT_DOUBLE_EQ(s.camera.fy, p.fy) << n;
    EXPECT_DOUBLE_EQ(s.camera.cx, p.cx) << n;
    EXPECT_DOUBLE_EQ(s.camera.cy, p.cy) << n;
    EXPECT_DOUBLE_EQ(s.camera.distortion.k1, p.distortion.k1) << n;
    EXPECT_DOUBLE_EQ(s.camera.distortion.k2, p.distortion.k2) << n;
    EXPECT_DOUBLE_EQ(s.camera.distortion.p1, p.distortion.p1) << n;
    EXPECT_DOUBLE_EQ(s.camera.distortion.p2, p.distortion.p2) << n;
    EXPECT_DOUBLE_EQ(s.camera.distortion.k3, p.distortion.k3) << n;
    EXPECT_DOUBLE_EQ(s.camera.depth_map_factor, p.depth_map_factor) << n;
    EXPECT_DOUBLE_EQ(s.camera.bf, 40.0) << n;
    EXPECT_DOUBLE_EQ(s.camera.th_depth, 40.0) << n;
    EXPECT_DOUBLE_EQ(s.camera.fps, 30.0) << n;
    EXPECT_TRUE(s.camera.rgb_order) << n;
    EXPECT_EQ(s.camera.width, 640) << n;
    EXPECT_EQ(s.camera.height, 480) << n;
    EXPECT_EQ(s.orb.n_features, 1000) << n;
    EXPECT_FLOAT_EQ(s.orb.scale_factor, 1.2f) << n;
    EXPECT_EQ(s.orb.n_levels, 8) << n;
    EXPECT_EQ(s.orb.ini_th_fast, 20) << n;
    EXPECT_EQ(s.orb.min_th_fast, 7) << n;
  }
}
