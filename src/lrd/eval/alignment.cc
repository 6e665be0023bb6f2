#include "lrd/eval/alignment.h"

#include <Eigen/SVD>

#include "lrd/util/error.h"

namespace lrd::eval {

Eigen::Isometry3d align_rigid(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& data) {
  if (model.cols() != data.cols() || model.cols() == 0) {
    throw Error("align_rigid: model and data need the same, non-zero number of points");
  }
  const Eigen::Vector3d model_mean = model.rowwise().mean();
  const Eigen::Vector3d data_mean = data.rowwise().mean();
  const Eigen::Matrix3Xd model_zc = model.colwise() - model_mean;
  const Eigen::Matrix3Xd data_zc = data.colwise() - data_mean;
  // W = sum_k outer(model_k, data_k); evaluate_ate.py decomposes W^T = U diag(d) Vh.
  const Eigen::Matrix3d w = model_zc * data_zc.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(w.transpose(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d& u = svd.matrixU();
  const Eigen::Matrix3d vh = svd.matrixV().transpose();
  Eigen::Matrix3d s = Eigen::Matrix3d::Identity();
  if (u.determinant() * vh.determinant() < 0.0) s(2, 2) = -1.0;  // a rotation, never a reflection
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = u * s * vh;
  transform.translation() = data_mean - transform.linear() * model_mean;
  return transform;
}

}  // namespace lrd::eval
