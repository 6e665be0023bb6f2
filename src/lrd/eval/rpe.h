#pragma once
// Relative pose error as TUM's evaluate_rpe.py computes it with --fixed_delta --delta_unit s, but over
// ALL pairs (the script samples 10,000 at random when there are more). For each estimated pose i,
// j is the estimated pose closest in time to t_i + delta (skipped when j is the last pose); both
// are matched to the closest ground-truth stamps, which must lie within 2x the median ground-truth
// period. Error E = inv(inv(P_j) P_i) * (inv(Q_j) Q_i), P estimate and Q ground truth (camera-to-world).
#include <cstddef>
#include <span>
#include <vector>

#include "lrd/eval/statistics.h"
#include "lrd/io/trajectory.h"

namespace lrd::eval {

struct RpePair {
  std::size_t est_i = 0, est_j = 0;  // indices into the estimate
  std::size_t gt_i = 0, gt_j = 0;    // indices into the ground truth
  double trans = 0.0;                // |translation of E|, metres (per delta seconds)
  double rot_deg = 0.0;              // rotation angle of E, degrees (per delta seconds)
};

struct RpeResult {
  std::vector<RpePair> pairs;  // in order of est_i
  ErrorStats trans;            // metres; m/s for delta = 1 s
  ErrorStats rot;              // degrees; deg/s for delta = 1 s
};

// Throws lrd::Error (naming no file) when the stamps barely overlap or fewer than 2 pairs remain.
[[nodiscard]] RpeResult compute_rpe(const io::Trajectory& ground_truth, const io::Trajectory& estimate,
                                    double delta = 1.0);

// find_closest_index() of evaluate_rpe.py, verbatim: a binary search that keeps the closest
// element it visits (not necessarily the closest overall on unsorted input). `sorted` must be non-empty.
[[nodiscard]] std::size_t find_closest_index(std::span<const double> sorted, double t);

}  // namespace lrd::eval
