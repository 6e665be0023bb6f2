// Motion-only BA: recovers a known pose from noisy matches with outliers, flags the outliers.
#include <gtest/gtest.h>

#include <random>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/geometry/se3.h"
#include "lrd/optim/pose_optimizer.h"

using lrd::optim::optimize_pose;
using lrd::optim::PoseObservation;

namespace {

struct Scenario {
  std::vector<PoseObservation> obs;
  std::vector<bool> is_outlier;
  Eigen::Isometry3d T_true;
};

Scenario make_scenario(const lrd::camera::PinholeCamera& cam, int n, double outlier_fraction, bool stereo,
                       unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(0, cam.width), uy(0, cam.height), uz(0.8, 4.0), unit(0, 1);
  std::normal_distribution<double> px(0.0, 1.0);
  Scenario s;
  lrd::geometry::Vector6d xi;
  xi << 0.1, -0.2, 0.05, 0.3, -0.1, 0.2;
  s.T_true = lrd::geometry::se3_exp(xi);
  for (int i = 0; i < n; ++i) {
    const double u = ux(rng), v = uy(rng), z = uz(rng);
    const Eigen::Vector3d p_c = cam.unproject(u, v, z);
    PoseObservation o;
    o.point_w = s.T_true.inverse() * p_c;
    const bool outlier = unit(rng) < outlier_fraction;
    o.pixel = outlier ? Eigen::Vector2d(ux(rng), uy(rng)) : Eigen::Vector2d(u + px(rng), v + px(rng));
    // The depth sensor's disparity bf / z is measured with the camera's disparity sigma.
    if (stereo) o.u_right = o.pixel.x() - cam.bf / z + (outlier ? 0.0 : cam.disparity_sigma * px(rng));
    s.obs.push_back(o);
    s.is_outlier.push_back(outlier);
  }
  return s;
}

double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

}  // namespace

TEST(PoseOptimizer, RecoversKnownPoseWithOutliers) {
  const auto cam = lrd::camera::camera_preset("tum3");
  for (bool stereo : {false, true}) {
    SCOPED_TRACE(stereo ? "stereo-like (RGB-D)" : "monocular");
    const Scenario s = make_scenario(cam, 300, 0.25, stereo, 42);
    lrd::geometry::Vector6d d;
    d << 0.03, -0.04, 0.05, 0.08, 0.05, -0.1;  // ~5 degrees and ~14 cm off
    const auto r = optimize_pose(cam, s.obs, lrd::geometry::se3_exp(d) * s.T_true);
    EXPECT_LT((r.T_cw.translation() - s.T_true.translation()).norm(), 0.01);
    EXPECT_LT(rotation_error_deg(r.T_cw, s.T_true), 0.2);
    int caught = 0, outliers = 0, false_alarms = 0;
    for (std::size_t i = 0; i < s.obs.size(); ++i) {
      outliers += s.is_outlier[i];
      caught += s.is_outlier[i] && r.outlier[i];
      false_alarms += !s.is_outlier[i] && r.outlier[i];
    }
    EXPECT_GE(caught, 0.97 * outliers);
    // Inliers with 1 px noise exceed the 95 % chi-square bound about 5 % of the time.
    EXPECT_LE(false_alarms, 0.1 * (300 - outliers));
    EXPECT_EQ(r.inliers, static_cast<int>(std::count(r.outlier.begin(), r.outlier.end(), false)));
  }
}

TEST(PoseOptimizer, ExactDataConvergesToTruth) {
  const auto cam = lrd::camera::camera_preset("tum1");
  Scenario s = make_scenario(cam, 60, 0.0, true, 7);
  for (std::size_t i = 0; i < s.obs.size(); ++i) {
    const Eigen::Vector3d p = s.T_true * s.obs[i].point_w;
    s.obs[i].pixel = cam.project(p);
    s.obs[i].u_right = s.obs[i].pixel.x() - cam.bf / p.z();
  }
  const auto start = s.T_true * lrd::geometry::se3_exp(lrd::geometry::Vector6d::Constant(0.02));
  const auto r = optimize_pose(cam, s.obs, start);
  EXPECT_LT((r.T_cw.translation() - s.T_true.translation()).norm(), 1e-6);
  EXPECT_LT(rotation_error_deg(r.T_cw, s.T_true), 1e-5);
  EXPECT_EQ(r.inliers, 60);
}

TEST(PoseOptimizer, TooFewObservationsIsNotACrash) {
  const auto cam = lrd::camera::camera_preset("tum3");
  const Scenario s = make_scenario(cam, 2, 0.0, false, 1);
  const auto r = optimize_pose(cam, s.obs, Eigen::Isometry3d::Identity());
  EXPECT_EQ(r.outlier.size(), 2u);
  EXPECT_TRUE(r.T_cw.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(PoseOptimizer, PointsBehindTheCameraAreOutliers) {
  const auto cam = lrd::camera::camera_preset("tum3");
  Scenario s = make_scenario(cam, 100, 0.0, false, 3);
  s.obs[0].point_w = s.T_true.inverse() * Eigen::Vector3d(0.1, 0.1, -2.0);
  const auto r = optimize_pose(cam, s.obs, s.T_true);
  EXPECT_TRUE(r.outlier[0]);
  EXPECT_LT((r.T_cw.translation() - s.T_true.translation()).norm(), 0.01);
}
