#pragma once
// A trajectory as the report pages draw it (docs/report.md): positions as x/y/z columns, aligned
// onto the ground truth as the ATE aligns it, with each pose's error. Shared by the run page and
// the benchmark page.
#include <cstddef>
#include <nlohmann/json.hpp>

#include "lrd/io/trajectory.h"

namespace lrd::report {

// Rounded so that a page stays small: 10 µm for positions, 1 µs for stamps.
[[nodiscard]] double round_to(double value, double step);

// Positions as x/y/z columns, as the pages read them: empty, and one position appended (rounded).
[[nodiscard]] nlohmann::json xyz_columns();
void push_xyz(nlohmann::json& columns, const Eigen::Vector3d& position);

// Every stride-th of n items keeps at most max_points of them (max_points 0: all).
[[nodiscard]] std::size_t stride_for(std::size_t n, std::size_t max_points);

// The estimate aligned onto the ground truth (TUM's evaluate_ate.py: rigid, no scale, stamps
// within 20 ms): {"frame", "t", "est", "gt", "error", "gt_path"}. At most `max_points` poses are
// kept (evenly spaced; 0: all). Throws lrd::Error when fewer than 2 stamps associate.
[[nodiscard]] nlohmann::json aligned_trajectory(const io::Trajectory& ground_truth,
                                                const io::Trajectory& estimate, std::size_t max_points = 0);

// Without ground truth: the estimate in the first camera's frame ({"frame", "t", "est"}).
[[nodiscard]] nlohmann::json own_frame_trajectory(const io::Trajectory& estimate);

}  // namespace lrd::report
