#pragma once
// Minimal SE(3) helpers on Eigen::Isometry3d: the exponential map used for pose updates, and the
// skew matrix. Tangent vectors are ordered (omega, nu): rotation first, then translation.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

namespace lrd::geometry {

using Vector6d = Eigen::Matrix<double, 6, 1>;

inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

// exp of a twist (omega, nu), as a rigid transform.
inline Eigen::Isometry3d se3_exp(const Vector6d& xi) {
  const Eigen::Vector3d w = xi.head<3>(), v = xi.tail<3>();
  const double theta = w.norm();
  const Eigen::Matrix3d W = skew(w);
  Eigen::Matrix3d R, V;
  if (theta < 1e-10) {
    R = Eigen::Matrix3d::Identity() + W;
    V = Eigen::Matrix3d::Identity() + 0.5 * W;
  } else {
    const double s = std::sin(theta), c = std::cos(theta), t2 = theta * theta;
    R = Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
    V = Eigen::Matrix3d::Identity() + (1.0 - c) / t2 * W + (theta - s) / (t2 * theta) * W * W;
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = V * v;
  return T;
}

// log of a rigid transform, as a twist (omega, nu): the inverse of se3_exp for rotations below pi.
inline Vector6d se3_log(const Eigen::Isometry3d& T) {
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(T.linear()).normalized());
  const double theta = aa.angle();
  const Eigen::Vector3d w = theta * aa.axis();
  const Eigen::Matrix3d W = skew(w);
  Eigen::Matrix3d V = Eigen::Matrix3d::Identity() + 0.5 * W;
  if (theta >= 1e-10) {
    const double s = std::sin(theta), c = std::cos(theta), t2 = theta * theta;
    V = Eigen::Matrix3d::Identity() + (1.0 - c) / t2 * W + (theta - s) / (t2 * theta) * W * W;
  }
  Vector6d xi;
  xi.head<3>() = w;
  xi.tail<3>() = V.partialPivLu().solve(T.translation());
  return xi;
}

// T to the real power s, along the screw motion: s = 1/n is the motion of one of n equal steps.
inline Eigen::Isometry3d se3_power(const Eigen::Isometry3d& T, double s) {
  return se3_exp(s * se3_log(T));
}

// The nearest rigid transform: products of rotations drift off orthonormality by rounding, and
// Isometry3d::inverse() (a transpose) turns that drift into real pose error, which the motion
// model then amplifies frame after frame. Every stored pose goes through this.
inline Eigen::Isometry3d orthonormalized(const Eigen::Isometry3d& T) {
  Eigen::Isometry3d r = T;
  r.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  return r;
}

}  // namespace lrd::geometry
