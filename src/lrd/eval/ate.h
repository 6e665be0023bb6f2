#pragma once
// Absolute trajectory error as TUM's evaluate_ate.py computes it: associate stamps (|dt| < max_dt),
// align the estimated positions rigidly onto the ground truth (no scale), and take the distance of
// each aligned estimated position to its ground-truth position.
#include <Eigen/Geometry>
#include <vector>

#include "lrd/eval/association.h"
#include "lrd/eval/statistics.h"
#include "lrd/io/trajectory.h"

namespace lrd::eval {

struct AteResult {
  std::vector<Match> matches;  // first: ground-truth index, second: estimate index; by gt stamp
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();  // maps estimate -> ground truth
  std::vector<double> errors;                                   // metres, one per match
  ErrorStats stats;
};

// Throws lrd::Error when fewer than 2 pairs associate (evaluate_ate.py's "Couldn't find matching
// timestamp pairs"); the message names no file, so callers add the file names.
[[nodiscard]] AteResult compute_ate(const io::Trajectory& ground_truth, const io::Trajectory& estimate,
                                    double max_dt = 0.02);

// The same errors under a given alignment instead of the best fit: a map-file session tracked in
// a loaded map is judged with the alignment of the session that made the map (docs/map-files.md).
[[nodiscard]] AteResult compute_ate(const io::Trajectory& ground_truth, const io::Trajectory& estimate,
                                    const Eigen::Isometry3d& alignment, double max_dt = 0.02);

[[nodiscard]] std::vector<double> timestamps(const io::Trajectory& trajectory);

}  // namespace lrd::eval
