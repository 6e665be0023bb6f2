#include "lrd/geometry/triangulation.h"

#include <Eigen/SVD>
#include <cmath>

#include "lrd/geometry/se3.h"

namespace lrd::geometry {

std::optional<Eigen::Vector3d> triangulate(const Eigen::Vector3d& xn1, const Eigen::Isometry3d& T1_cw,
                                           const Eigen::Vector3d& xn2, const Eigen::Isometry3d& T2_cw) {
  const Eigen::Matrix<double, 3, 4> P1 = T1_cw.matrix().topRows<3>();
  const Eigen::Matrix<double, 3, 4> P2 = T2_cw.matrix().topRows<3>();
  Eigen::Matrix4d A;
  A.row(0) = xn1.x() * P1.row(2) - P1.row(0);
  A.row(1) = xn1.y() * P1.row(2) - P1.row(1);
  A.row(2) = xn2.x() * P2.row(2) - P2.row(0);
  A.row(3) = xn2.y() * P2.row(2) - P2.row(1);
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d x = svd.matrixV().col(3);
  if (std::abs(x(3)) < 1e-12) return std::nullopt;
  return Eigen::Vector3d(x.head<3>() / x(3));
}

Eigen::Matrix3d fundamental_matrix(const Eigen::Isometry3d& T1_cw, const Eigen::Isometry3d& T2_cw,
                                   const Eigen::Matrix3d& K) {
  const Eigen::Isometry3d T12 = T1_cw * T2_cw.inverse();  // camera 2 -> camera 1
  const Eigen::Matrix3d E = skew(T12.translation()) * T12.rotation();
  const Eigen::Matrix3d K_inv = K.inverse();
  return K_inv.transpose() * E * K_inv;
}

}  // namespace lrd::geometry
