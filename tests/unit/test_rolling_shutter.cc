// Rolling-shutter compensation (tracking/rolling_shutter.h): keypoints that a turning and moving
// camera saw row by row go back to where a global shutter at the frame's stamp would have seen
// them, with the depth they had then.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "lrd/data/frame.h"
#include "lrd/geometry/se3.h"
#include "lrd/tracking/rolling_shutter.h"
#include "lrd/util/error.h"

namespace {

using lrd::camera::PinholeCamera;
using lrd::geometry::Vector6d;

constexpr double kPeriod = 1.0 / 30.0;

// About TUM's halfsphere pace: ~21 deg/s of rotation, 0.23 m/s of translation.
Vector6d twist_per_second() {
  Vector6d xi;
  xi << 0.10, 0.33, 0.05, 0.20, -0.05, 0.10;
  return xi;
}

PinholeCamera rolling_camera(double readout) {
  PinholeCamera cam;
  cam.readout_time = readout;
  return cam;
}

// Where a rolling shutter sees the point p (camera frame at the stamp): on the row whose instant
// puts p on that row (a fixed point, found by iteration).
Eigen::Vector3d seen_by_its_row(const PinholeCamera& cam, const Eigen::Vector3d& p) {
  Eigen::Vector3d q = p;
  for (int it = 0; it < 30; ++it) {
    const double dt = cam.readout_time * (cam.project(q).y() / (cam.height - 1) - 0.5);
    q = lrd::geometry::se3_exp(dt * twist_per_second()) * p;
  }
  return q;
}

struct RollingFrame {
  std::vector<Eigen::Vector3d> points;  // camera frame at the stamp
  lrd::data::Frame frame;
};

// Points on a slanted wall over the whole image (a last one far away, without depth), seen by
// the rolling shutter.
RollingFrame rolling_frame(const PinholeCamera& cam) {
  std::vector<Eigen::Vector3d> points;
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 12; ++c) {
      const double u = 30.0 + 50.0 * c, v = 25.0 + 53.0 * r;
      points.push_back(cam.unproject(u, v, 1.5 + 0.002 * u + 0.001 * v));
    }
  points.push_back(cam.unproject(100.0, 400.0, 30.0));
  lrd::data::Frame::SavedFeatures f;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d q = seen_by_its_row(cam, points[i]);
    const Eigen::Vector2d uv = cam.project(q);
    const cv::KeyPoint kp(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31.0f, 0.0f, 1.0f, 0);
    f.keypoints.push_back(kp);
    f.undistorted.push_back(kp);
    const bool with_depth = i + 1 < points.size();
    f.depth.push_back(with_depth ? static_cast<float>(q.z()) : -1.0f);
    f.u_right.push_back(with_depth ? kp.pt.x - static_cast<float>(cam.bf / q.z()) : -1.0f);
  }
  f.descriptors = cv::Mat::zeros(static_cast<int>(points.size()), 32, CV_8U);
  f.level_sigma2 = f.inv_level_sigma2 = f.scale_factors = {1.0f};
  f.bounds = cv::Rect2f(0.0f, 0.0f, static_cast<float>(cam.width), static_cast<float>(cam.height));
  return {points, lrd::data::Frame(7, 1.0, cam, std::move(f), Eigen::Isometry3d::Identity())};
}

double pixel_error(const lrd::data::Frame& frame, std::size_t i, const Eigen::Vector2d& truth) {
  const cv::Point2f& pt = frame.undistorted()[i].pt;
  return std::hypot(pt.x - truth.x(), pt.y - truth.y());
}

TEST(RollingShutter, KeypointsGoBackToTheStamp) {
  const PinholeCamera cam = rolling_camera(0.028);
  RollingFrame rf = rolling_frame(cam);
  const std::size_t n = rf.points.size();
  double before = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    before = std::max(before, pixel_error(rf.frame, i, cam.project(rf.points[i])));
  EXPECT_GT(before, 2.0);  // the shear is worth compensating

  const Eigen::Isometry3d velocity = lrd::geometry::se3_exp(kPeriod * twist_per_second());
  lrd::tracking::compensate_rolling_shutter(rf.frame, velocity, kPeriod);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    EXPECT_LT(pixel_error(rf.frame, i, cam.project(rf.points[i])), 0.01) << "keypoint " << i;
    EXPECT_NEAR(rf.frame.depth(i), rf.points[i].z(), 1e-5) << "keypoint " << i;
    EXPECT_NEAR(rf.frame.u_right(i), rf.frame.undistorted()[i].pt.x - cam.bf / rf.frame.depth(i), 1e-3);
    // The grid finds each keypoint where it is now.
    const cv::Point2f& pt = rf.frame.undistorted()[i].pt;
    const auto near = rf.frame.features_in_area(pt.x, pt.y, 1.0f);
    EXPECT_NE(std::find(near.begin(), near.end(), i), near.end()) << "keypoint " << i;
  }
  // Without depth the rotation alone: right for a far point, which stays without depth.
  EXPECT_LT(pixel_error(rf.frame, n - 1, cam.project(rf.points[n - 1])), 0.1);
  EXPECT_LT(rf.frame.depth(n - 1), 0.0f);
  EXPECT_LT(rf.frame.u_right(n - 1), 0.0f);
  // The detected positions stay as detected.
  EXPECT_GT(std::abs(rf.frame.keypoints()[0].pt.y - rf.frame.undistorted()[0].pt.y), 0.5f);
}

TEST(RollingShutter, AGlobalShutterOrAStillCameraMovesNothing) {
  const Eigen::Isometry3d velocity = lrd::geometry::se3_exp(kPeriod * twist_per_second());
  RollingFrame global = rolling_frame(rolling_camera(0.0));
  const auto positions = global.frame.undistorted();
  lrd::tracking::compensate_rolling_shutter(global.frame, velocity, kPeriod);
  for (std::size_t i = 0; i < global.frame.size(); ++i)
    EXPECT_EQ(global.frame.undistorted()[i].pt, positions[i].pt);

  RollingFrame still = rolling_frame(rolling_camera(0.028));
  const auto seen = still.frame.undistorted();
  lrd::tracking::compensate_rolling_shutter(still.frame, Eigen::Isometry3d::Identity(), kPeriod);
  for (std::size_t i = 0; i < still.frame.size(); ++i) {
    EXPECT_NEAR(still.frame.undistorted()[i].pt.x, seen[i].pt.x, 1e-3);
    EXPECT_NEAR(still.frame.undistorted()[i].pt.y, seen[i].pt.y, 1e-3);
  }
}

TEST(RollingShutter, MovingKeypointsNeedOnePositionAndDepthEach) {
  RollingFrame rf = rolling_frame(rolling_camera(0.028));
  EXPECT_THROW(rf.frame.move_keypoints({cv::Point2f(1.0f, 2.0f)}, {1.0f}), lrd::Error);
}

}  // namespace
