// The loop closer's rigid transform: recovered from 3D-3D matches despite outliers, and
// deterministic.
#include <gtest/gtest.h>

#include <random>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/loop/rigid_transform_ransac.h"

namespace {

using lrd::loop::PointCorrespondence;

std::vector<PointCorrespondence> make_matches(const Eigen::Isometry3d& T_12, int n, int outliers,
                                              unsigned seed) {
  const lrd::camera::PinholeCamera cam = lrd::camera::camera_preset("tum3");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-1.0, 1.0), uz(1.0, 4.0), noise(-0.002, 0.002);
  std::vector<PointCorrespondence> m;
  for (int i = 0; i < n; ++i) {
    // A point in camera 2 that both cameras see.
    Eigen::Vector3d p2(ux(rng), 0.7 * ux(rng), uz(rng));
    Eigen::Vector3d p1 = T_12 * p2;
    if (i < outliers) p1 += Eigen::Vector3d(0.4 + ux(rng), 0.3, 0.2);  // a wrong match
    PointCorrespondence c;
    c.p1 = p1 + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    c.p2 = p2;
    c.px1 = cam.project(p1);
    c.px2 = cam.project(p2);
    m.push_back(c);
  }
  return m;
}

TEST(RigidRansac, RecoversTransformDespiteOutliers) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.25, -0.05, 0.1);
  const auto matches = make_matches(T, 120, 40, 7);
  const auto r = lrd::loop::estimate_rigid_ransac(matches, lrd::camera::camera_preset("tum3"));
  ASSERT_TRUE(r.ok);
  EXPECT_GE(r.inliers, 75);
  EXPECT_LE(r.inliers, 80);
  for (int i = 0; i < 40; ++i) EXPECT_FALSE(r.inlier[static_cast<std::size_t>(i)]) << i;
  EXPECT_LT((r.T_12.translation() - T.translation()).norm(), 0.005);
  EXPECT_LT(Eigen::AngleAxisd(r.T_12.linear().transpose() * T.linear()).angle(), 0.003);
  // Same input, same answer.
  const auto again = lrd::loop::estimate_rigid_ransac(matches, lrd::camera::camera_preset("tum3"));
  EXPECT_TRUE(again.T_12.isApprox(r.T_12, 0.0));
}

TEST(RigidRansac, RefusesWhenTooFewAgree) {
  const auto matches = make_matches(Eigen::Isometry3d::Identity(), 30, 25, 3);
  lrd::loop::RigidRansacParams p;
  p.min_inliers = 20;
  EXPECT_FALSE(lrd::loop::estimate_rigid_ransac(matches, lrd::camera::camera_preset("tum3"), p).ok);
}

}  // namespace
