#include "lrd/eval/rpe.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "lrd/eval/ate.h"
#include "lrd/util/error.h"

namespace lrd::eval {

std::size_t find_closest_index(std::span<const double> sorted, double t) {
  std::size_t beginning = 0;
  double difference = std::abs(sorted[0] - t);
  std::size_t best = 0;
  std::size_t end = sorted.size();
  while (beginning < end) {
    const std::size_t middle = (end + beginning) / 2;
    if (std::abs(sorted[middle] - t) < difference) {
      difference = std::abs(sorted[middle] - t);
      best = middle;
    }
    if (t == sorted[middle]) return middle;
    if (sorted[middle] > t) {
      end = middle;
    } else {
      beginning = middle + 1;
    }
  }
  return best;
}

RpeResult compute_rpe(const io::Trajectory& ground_truth, const io::Trajectory& estimate, double delta) {
  if (ground_truth.empty() || estimate.empty())
    throw Error("RPE needs a non-empty ground truth and estimate");
  const std::vector<double> stamps_gt = timestamps(ground_truth);
  const std::vector<double> stamps_est = timestamps(estimate);

  // evaluate_rpe.py's overlap check: estimated stamps reached by a round trip est -> gt -> est.
  std::set<double> stamps_est_return;
  for (double t_est : stamps_est) {
    const double t_gt = stamps_gt[find_closest_index(stamps_gt, t_est)];
    stamps_est_return.insert(stamps_est[find_closest_index(stamps_est, t_gt)]);
  }
  if (stamps_est_return.size() < 2) {
    throw Error("the timestamps of ground truth and estimate barely overlap (wrong files?)");
  }

  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < stamps_est.size(); ++i) {
    const std::size_t j = find_closest_index(stamps_est, stamps_est[i] + delta);
    if (j != stamps_est.size() - 1) pairs.emplace_back(i, j);
  }

  // With a single ground-truth pose this is NaN and, as in the script, no pair is rejected.
  std::vector<double> gt_periods;
  for (std::size_t k = 1; k < stamps_gt.size(); ++k) gt_periods.push_back(stamps_gt[k] - stamps_gt[k - 1]);
  const double gt_max_time_difference = 2.0 * median(gt_periods);

  RpeResult result;
  for (const auto& [i, j] : pairs) {
    const std::size_t gi = find_closest_index(stamps_gt, stamps_est[i]);
    const std::size_t gj = find_closest_index(stamps_gt, stamps_est[j]);
    if (std::abs(stamps_gt[gi] - stamps_est[i]) > gt_max_time_difference ||
        std::abs(stamps_gt[gj] - stamps_est[j]) > gt_max_time_difference) {
      continue;
    }
    const Eigen::Isometry3d& p_i = estimate[i].pose;
    const Eigen::Isometry3d& p_j = estimate[j].pose;
    const Eigen::Isometry3d& q_i = ground_truth[gi].pose;
    const Eigen::Isometry3d& q_j = ground_truth[gj].pose;
    // ominus(a, b) = inv(a) * b; the script's order, see docs/evaluation.md.
    const Eigen::Isometry3d rel_est = p_j.inverse(Eigen::Isometry) * p_i;
    const Eigen::Isometry3d rel_gt = q_j.inverse(Eigen::Isometry) * q_i;
    const Eigen::Isometry3d error44 = rel_est.inverse(Eigen::Isometry) * rel_gt;
    RpePair pair{i, j, gi, gj, 0.0, 0.0};
    pair.trans = error44.translation().norm();
    const double cos_angle = std::clamp((error44.linear().trace() - 1.0) / 2.0, -1.0, 1.0);
    pair.rot_deg = std::acos(cos_angle) * 180.0 / std::numbers::pi;
    result.pairs.push_back(pair);
  }
  if (result.pairs.size() < 2) {
    throw Error(
        fmt::format("only {} RPE pair(s) with delta {} s have ground truth within {:.4f} s; need at least 2",
                    result.pairs.size(), delta, gt_max_time_difference));
  }
  std::vector<double> trans, rot;
  for (const RpePair& p : result.pairs) {
    trans.push_back(p.trans);
    rot.push_back(p.rot_deg);
  }
  result.trans = compute_stats(trans);
  result.rot = compute_stats(rot);
  return result;
}

}  // namespace lrd::eval
