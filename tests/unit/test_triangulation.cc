// Two-view geometry: DLT triangulation recovers exact points, the fundamental matrix satisfies
// the epipolar constraint in the documented order (x1' F12 x2 = 0), and degenerate ray pairs
// give no point (or at least none off the ray).
#include <gtest/gtest.h>

#include <random>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/geometry/se3.h"
#include "lrd/geometry/triangulation.h"

using lrd::geometry::fundamental_matrix;
using lrd::geometry::triangulate;

namespace {

Eigen::Isometry3d random_pose(std::mt19937& rng, double rot, double trans) {
  std::uniform_real_distribution<double> r(-rot, rot), t(-trans, trans);
  lrd::geometry::Vector6d xi;
  xi << r(rng), r(rng), r(rng), t(rng), t(rng), t(rng);
  return lrd::geometry::se3_exp(xi);
}

Eigen::Vector3d normalised(const Eigen::Isometry3d& T_cw, const Eigen::Vector3d& x) {
  const Eigen::Vector3d p = T_cw * x;
  return p / p.z();
}

// Distance (pixels) of pixel x1 from the epipolar line F12 x2 in view 1.
double line_distance(const Eigen::Matrix3d& F12, const Eigen::Vector2d& x1, const Eigen::Vector2d& x2) {
  const Eigen::Vector3d l = F12 * x2.homogeneous();
  return std::abs(x1.homogeneous().dot(l)) / l.head<2>().norm();
}

}  // namespace

TEST(Triangulation, RecoversRandomPointsFromTwoPosedViews) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(-1.5, 1.5), uz(1.0, 6.0);
  int tested = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Isometry3d T1 = random_pose(rng, 0.2, 0.5), T2 = random_pose(rng, 0.2, 0.5);
    for (int k = 0; k < 20; ++k) {
      // A point in front of camera 1 (and, checked, of camera 2).
      const Eigen::Vector3d x = T1.inverse() * Eigen::Vector3d(ux(rng), ux(rng), uz(rng));
      if ((T2 * x).z() < 0.5 || (T1.translation() - T2.translation()).norm() < 0.05) continue;
      const auto r = triangulate(normalised(T1, x), T1, normalised(T2, x), T2);
      ASSERT_TRUE(r.has_value());
      EXPECT_LT((*r - x).norm(), 1e-9) << "trial " << trial << " point " << k;
      ++tested;
    }
  }
  EXPECT_GT(tested, 800);
}

TEST(Triangulation, NoisyRaysGiveANearbyPoint) {
  // Half a pixel of noise on a 20 cm baseline at 2 m: the point moves by millimetres to centimetres
  // (depth error ~ z^2 / (f b) per pixel = 3.7 cm), never wildly.
  const auto cam = lrd::camera::camera_preset("tum3");
  std::mt19937 rng(5);
  std::normal_distribution<double> px(0.0, 0.5 / cam.fx);
  const Eigen::Isometry3d T1 = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T2 = Eigen::Isometry3d::Identity();
  T2.translation() = Eigen::Vector3d(-0.2, 0.0, 0.0);
  double worst = 0.0;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d x(0.5 * std::sin(k), 0.4 * std::cos(3 * k), 2.0);
    Eigen::Vector3d a = normalised(T1, x), b = normalised(T2, x);
    a.head<2>() += Eigen::Vector2d(px(rng), px(rng));
    b.head<2>() += Eigen::Vector2d(px(rng), px(rng));
    const auto r = triangulate(a, T1, b, T2);
    ASSERT_TRUE(r.has_value());
    worst = std::max(worst, (*r - x).norm());
  }
  EXPECT_LT(worst, 0.1);
  EXPECT_GT(worst, 1e-4);  // the noise did reach the result
}

TEST(Triangulation, ParallelRaysAreAtInfinity) {
  // Same orientation, a pure translation, the same normalised coordinates in both views: the
  // rays are parallel and meet only at infinity.
  Eigen::Isometry3d T1 = Eigen::Isometry3d::Identity(), T2 = Eigen::Isometry3d::Identity();
  T2.translation() = Eigen::Vector3d(-0.3, 0.1, 0.05);
  for (const Eigen::Vector3d& xn :
       {Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(0.2, -0.1, 1.0), Eigen::Vector3d(-0.45, 0.3, 1.0)}) {
    EXPECT_FALSE(triangulate(xn, T1, xn, T2).has_value()) << xn.transpose();
  }
  // Also with a rotated rig: the rays are parallel in the world.
  const Eigen::Isometry3d R =
      lrd::geometry::se3_exp((lrd::geometry::Vector6d() << 0.1, -0.3, 0.2, 0, 0, 0).finished());
  const Eigen::Isometry3d R1 = R * T1, R2 = R * T2;  // both rotated the same way about their own centres
  EXPECT_FALSE(
      triangulate(Eigen::Vector3d(0.1, 0.1, 1.0), R1, Eigen::Vector3d(0.1, 0.1, 1.0), R2).has_value());
}

TEST(Triangulation, ZeroBaselineNeverGivesAPointOffTheRay) {
  // Two identical cameras and the same ray: a rank-deficient system whose null space holds the
  // camera centre and the ray direction. Any answer must at least lie on that ray.
  const Eigen::Isometry3d T =
      lrd::geometry::se3_exp((lrd::geometry::Vector6d() << 0.05, 0.1, -0.02, 0.3, -0.2, 0.1).finished());
  const Eigen::Vector3d xn(0.15, -0.2, 1.0);
  const auto r = triangulate(xn, T, xn, T);
  // Precondition: for this pose and ray the solver does return a point (the camera centre's
  // component of the null space dominates), so the check below always runs. Should triangulate()
  // learn to reject a zero baseline, this becomes EXPECT_FALSE(r.has_value()).
  ASSERT_TRUE(r.has_value()) << "no point any more: replace the check below by EXPECT_FALSE(r)";
  const Eigen::Vector3d pc = T * *r;
  EXPECT_LT(pc.cross(xn).norm(), 1e-9 * std::max(1.0, pc.norm())) << pc.transpose();
}

TEST(Triangulation, FundamentalMatrixEpipolarConstraint) {
  const auto cam = lrd::camera::camera_preset("tum1");
  const Eigen::Matrix3d K = cam.K();
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> ux(0, cam.width), uy(0, cam.height), uz(0.7, 5.0);
  const Eigen::Isometry3d T1 = random_pose(rng, 0.3, 1.0);
  const Eigen::Isometry3d T2 =
      lrd::geometry::se3_exp((lrd::geometry::Vector6d() << 0.05, -0.08, 0.03, 0.25, 0.05, -0.1).finished()) *
      T1;
  const Eigen::Matrix3d F12 = fundamental_matrix(T1, T2, K);
  EXPECT_NEAR(F12.determinant(), 0.0, 1e-12 * F12.norm() * F12.norm() * F12.norm());
  int swapped_far = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d x = T1.inverse() * cam.unproject(ux(rng), uy(rng), uz(rng));
    const Eigen::Vector3d p2 = T2 * x;
    if (p2.z() <= 0.1) continue;
    const Eigen::Vector2d x1 = cam.project(T1 * x), x2 = cam.project(p2);
    EXPECT_LT(line_distance(F12, x1, x2), 1e-8);
    // The other way round: x2 against the line F21 x1 with F21 = F12'.
    EXPECT_LT(line_distance(F12.transpose(), x2, x1), 1e-8);
    // The order matters: F12 does not map view-1 pixels to lines in view 1.
    swapped_far += line_distance(F12, x2, x1) > 1.0;
  }
  EXPECT_GT(swapped_far, 250);
  // Same pose: no epipolar geometry (F vanishes).
  EXPECT_LT(fundamental_matrix(T1, T1, K).norm(), 1e-12);
}

TEST(Triangulation, FundamentalMatrixEpipolesAreItsNullSpaces) {
  const auto cam = lrd::camera::camera_preset("tum3");
  const Eigen::Matrix3d K = cam.K();
  const Eigen::Isometry3d T1 =
      lrd::geometry::se3_exp((lrd::geometry::Vector6d() << 0.02, 0.1, 0, 0.1, 0, 0).finished());
  const Eigen::Isometry3d T2 =
      lrd::geometry::se3_exp((lrd::geometry::Vector6d() << -0.05, 0.0, 0.1, -0.3, 0.1, 0.4).finished());
  const Eigen::Matrix3d F12 = fundamental_matrix(T1, T2, K);
  // e2: camera 1's centre seen in view 2; e1: camera 2's centre seen in view 1.
  const Eigen::Vector3d e2 = K * (T2 * T1.inverse().translation());
  const Eigen::Vector3d e1 = K * (T1 * T2.inverse().translation());
  EXPECT_LT((F12 * e2).norm() / (F12.norm() * e2.norm()), 1e-12);
  EXPECT_LT((F12.transpose() * e1).norm() / (F12.norm() * e1.norm()), 1e-12);
}
