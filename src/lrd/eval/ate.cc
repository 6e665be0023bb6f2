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

AteResult compute_ate(const io::Trajectory& ground_truth, const io::Trajectory& estimate, double max_dt) {
  AteResult result;
  result.matches = associate(timestamps(ground_truth), timestamps(estimate), max_dt);
  if (result.matches.size() < 2) {
    throw Error(
        fmt::format("only {} estimated pose(s) have a ground-truth timestamp within {} s; need at least 2 "
                    "(wrong sequence, or timestamps in different units?)",
                    result.matches.size(), max_dt));
  }
  const auto n = static_cast<Eigen::Index>(result.matches.size());
  Eigen::Matrix3Xd gt_xyz(3, n), est_xyz(3, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Match& m = result.matches[static_cast<std::size_t>(k)];
    gt_xyz.col(k) = ground_truth[m.first].pose.translation();
    est_xyz.col(k) = estimate[m.second].pose.translation();
  }
  result.alignment = align_rigid(est_xyz, gt_xyz);
  const Eigen::Matrix3Xd residual = (result.alignment * est_xyz) - gt_xyz;
  result.errors.resize(result.matches.size());
  for (Eigen::Index k = 0; k < n; ++k) result.errors[static_cast<std::size_t>(k)] = residual.col(k).norm();
  result.stats = compute_stats(result.errors);
  return result;
}

}  // namespace lrd::eval
