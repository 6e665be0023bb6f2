#include <gtest/gtest.h>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/util/error.h"

using lrd::camera::camera_preset;

TEST(CameraPreset, PublishedTumCalibration) {
  const auto fr1 = camera_preset("tum1");
  EXPECT_DOUBLE_EQ(fr1.fx, 517.306408);
  EXPECT_DOUBLE_EQ(fr1.cy, 255.313989);
  EXPECT_DOUBLE_EQ(fr1.distortion.k3, 1.163314);
  EXPECT_DOUBLE_EQ(fr1.depth_map_factor, 5000.0);
  const auto fr2 = camera_preset("tum2");
  EXPECT_DOUBLE_EQ(fr2.fy, 521.007327);
  EXPECT_DOUBLE_EQ(fr2.distortion.p2, -0.000105);
  EXPECT_DOUBLE_EQ(fr2.depth_map_factor, 5208.0);
  const auto fr3 = camera_preset("tum3");
  EXPECT_DOUBLE_EQ(fr3.fx, 535.4);
  EXPECT_TRUE(fr3.distortion.is_zero());
}

TEST(CameraPreset, UnknownNameNamesValidOnes) {
  try {
    (void)camera_preset("tum4");
    FAIL() << "expected lrd::Error";
  } catch (const lrd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("tum4"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("tum3"), std::string::npos);
  }
}

TEST(PinholeCamera, ProjectUnprojectRoundTrip) {
  const auto cam = camera_preset("tum3");
  const Eigen::Vector3d p(0.3, -0.2, 2.5);
  const Eigen::Vector2d uv = cam.project(p);
  EXPECT_TRUE(cam.unproject(uv.x(), uv.y(), p.z()).isApprox(p, 1e-12));
}
