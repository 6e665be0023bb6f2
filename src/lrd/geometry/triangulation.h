#pragma once
// Two-view geometry used by local mapping: linear (DLT) triangulation of a point from two
// normalised image rays, and the fundamental matrix between two posed views.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

namespace lrd::geometry {

// Point in the world frame seen at normalised coordinates xn1 = (x, y, 1) by camera 1 (T1_cw)
// and xn2 by camera 2 (T2_cw), by the homogeneous DLT with SVD (ORB-SLAM2's Triangulate).
// Empty when the solution is at infinity.
[[nodiscard]] std::optional<Eigen::Vector3d> triangulate(const Eigen::Vector3d& xn1,
                                                         const Eigen::Isometry3d& T1_cw,
                                                         const Eigen::Vector3d& xn2,
                                                         const Eigen::Isometry3d& T2_cw);

// F12 with x1' F12 x2 = 0 for pixels x1 in view 1 and x2 in view 2 (same intrinsics K).
[[nodiscard]] Eigen::Matrix3d fundamental_matrix(const Eigen::Isometry3d& T1_cw,
                                                 const Eigen::Isometry3d& T2_cw, const Eigen::Matrix3d& K);

}  // namespace lrd::geometry
