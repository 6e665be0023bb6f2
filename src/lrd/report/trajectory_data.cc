#include "lrd/report/trajectory_data.h"

#include <algorithm>
#include <cmath>

#include "lrd/eval/ate.h"

namespace lrd::report {
using nlohmann::json;

double round_to(double value, double step) {
  return std::round(value / step) * step;
}

json xyz_columns() {
  return {{"x", json::array()}, {"y", json::array()}, {"z", json::array()}};
}

void push_xyz(json& xyz, const Eigen::Vector3d& p) {
  xyz["x"].push_back(round_to(p.x(), 1e-5));
  xyz["y"].push_back(round_to(p.y(), 1e-5));
  xyz["z"].push_back(round_to(p.z(), 1e-5));
}

std::size_t stride_for(std::size_t n, std::size_t max_points) {
  return max_points == 0 ? 1 : std::max<std::size_t>(1, (n + max_points - 1) / max_points);
}

json aligned_trajectory(const io::Trajectory& gt, const io::Trajectory& est, std::size_t max_points) {
  const eval::AteResult ate = eval::compute_ate(gt, est);
  json j = {{"frame", "ground truth (world)"},
            {"t", json::array()},
            {"est", xyz_columns()},
            {"gt", xyz_columns()},
            {"error", json::array()},
            {"gt_path", xyz_columns()}};
  for (std::size_t i = 0; i < ate.matches.size(); i += stride_for(ate.matches.size(), max_points)) {
    const io::StampedPose& e = est[ate.matches[i].second];
    j["t"].push_back(round_to(e.timestamp, 1e-6));
    push_xyz(j["est"], ate.alignment * e.pose.translation());
    push_xyz(j["gt"], gt[ate.matches[i].first].pose.translation());
    j["error"].push_back(round_to(ate.errors[i], 1e-5));
  }
  // The whole ground-truth path beside it: a few thousand points at most.
  const std::size_t step = stride_for(gt.size(), max_points == 0 ? 3000 : max_points);
  for (std::size_t i = 0; i < gt.size(); i += step) push_xyz(j["gt_path"], gt[i].pose.translation());
  return j;
}

json own_frame_trajectory(const io::Trajectory& est) {
  json j = {
      {"frame", "the first camera's frame (no ground truth)"}, {"t", json::array()}, {"est", xyz_columns()}};
  for (const io::StampedPose& e : est) {
    j["t"].push_back(round_to(e.timestamp, 1e-6));
    push_xyz(j["est"], e.pose.translation());
  }
  return j;
}

}  // namespace lrd::report
