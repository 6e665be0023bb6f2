#pragma once
// Closed-form rigid alignment without scale (Horn / Umeyama via SVD), as align() in TUM's
// evaluate_ate.py: finds R, t minimising sum |R * model_k + t - data_k|^2, with the reflection fix.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lrd::eval {

// model: estimated positions (3xN), data: ground-truth positions (3xN), column k of each paired.
// Returns the transform that maps the estimate onto the ground truth.
[[nodiscard]] Eigen::Isometry3d align_rigid(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& data);

}  // namespace lrd::eval
