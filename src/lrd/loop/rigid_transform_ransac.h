#pragma once
// Rigid transform between two keyframes from matched map points (loop closing, RGB-D: the scale
// is known, so ORB-SLAM2's Sim3Solver becomes an SE(3) one): RANSAC over minimal sets of three
// 3D-3D correspondences solved in closed form (Umeyama / Horn, no scaling), inliers judged by
// reprojection in both images (chi-square 9.21, 2 dof at 99 %, as ORB-SLAM2), then a
// least-squares refit on all inliers.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "lrd/camera/pinhole_camera.h"

namespace lrd::loop {

struct PointCorrespondence {
  Eigen::Vector3d p1;                     // point in camera 1's frame
  Eigen::Vector3d p2;                     // the matched point in camera 2's frame
  Eigen::Vector2d px1;                    // its keypoint in image 1 (undistorted)
  Eigen::Vector2d px2;                    // ... and in image 2
  double sigma2_1 = 1.0, sigma2_2 = 1.0;  // keypoint variances (pyramid level)
};

struct RigidRansacParams {
  int iterations = 300;
  int min_inliers = 20;
  double chi2 = 9.21;
  std::uint64_t seed = 0x100bC105Eull;
};

struct RigidRansacResult {
  bool ok = false;
  Eigen::Isometry3d T_12 = Eigen::Isometry3d::Identity();  // camera 2 -> camera 1
  std::vector<bool> inlier;
  int inliers = 0;
};

// Least-squares rigid transform mapping `from` onto `to` (at least 3 points).
[[nodiscard]] Eigen::Isometry3d fit_rigid(const std::vector<Eigen::Vector3d>& from,
                                          const std::vector<Eigen::Vector3d>& to);

[[nodiscard]] RigidRansacResult estimate_rigid_ransac(const std::vector<PointCorrespondence>& matches,
                                                      const camera::PinholeCamera& camera,
                                                      const RigidRansacParams& params = {});

}  // namespace lrd::loop
