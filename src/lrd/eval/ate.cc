#include "lrd/eval/ate.h"

#include <fmt/format.h>

#include "lrd/eval/alignment.h"
#include "lrd/util/error.h"

namespace lrd::eval {

std::vector<double> timestamps(const io::Trajectory& trajectory) {
  std::vector<double> stamps;
  stamps.reserve(trajectory.size());
  for (const io::StampedPose& p : trajectory) stamps.push_back(p.timestamp);
  return stamps;
}

namespace {
// Associated positions; both `compute_ate`s need at least 2 pairs.
AteResult associated(const io::Trajectory& ground_truth, const io::Trajectory& estimate, double max_dt,
                     Eigen::Matrix3Xd& gt_xyz, Eigen::Matrix3Xd& est_xyz) {
  AteResult result;
  result.matches = associate(timestamps(ground_truth), timestamps(estimate), max_dt);
  if (result.matches.size() < 2) {
    throw Error(
        fmt::format("only {} estimated pose(s) have a ground-truth timestamp within {} s; need at least 2 "
                    "(wrong sequence, or timestamps in different units?)",
                    result.matches.size(), max_dt));
  }
  const auto n = static_cast<Eigen::Index>(result.matches.size());
  gt_xyz.resize(3, n);
  est_xyz.resize(3, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Match& m = result.matches[static_cast<std::size_t>(k)];
    gt_xyz.col(k) = ground_truth[m.first].pose.translation();
    est_xyz.col(k) = estimate[m.second].pose.translation();
  }
  return result;
}

void measure(AteResult& result, const Eigen::Matrix3Xd& gt_xyz, const Eigen::Matrix3Xd& est_xyz) {
  const auto n = gt_xyz.cols();
  const Eigen::Matrix3Xd residual = (result.alignment * est_xyz) - gt_xyz;
  result.errors.resize(result.matches.size());
  for (Eigen::Index k = 0; k < n; ++k) result.errors[static_cast<std::size_t>(k)] = residual.col(k).norm();
  result.stats = compute_stats(result.errors);
}
}  // namespace

AteResult compute_ate(const io::Trajectory& ground_truth, const io::Trajectory& estimate, double max_dt) {
  Eigen::Matrix3Xd gt_xyz, est_xyz;
  AteResult result = associated(ground_truth, estimate, max_dt, gt_xyz, est_xyz);
  result.alignment = align_rigid(est_xyz, gt_xyz);
  measure(result, gt_xyz, est_xyz);
  return result;
}

AteResult compute_ate(const io::Trajectory& ground_truth, const io::Trajectory& estimate,
                      const Eigen::Isometry3d& alignment, double max_dt) {
  Eigen::Matrix3Xd gt_xyz, est_xyz;
  AteResult result = associated(ground_truth, estimate, max_dt, gt_xyz, est_xyz);
  result.alignment = alignment;
  measure(result, gt_xyz, est_xyz);
  return result;
}

}  // namespace lrd::eval
