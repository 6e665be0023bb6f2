#include "lrd/eval/motion_statistics.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace lrd::eval {

MotionStatistics motion_statistics(const io::Trajectory& trajectory) {
  MotionStatistics s;
  if (trajectory.size() < 2) return s;
  s.duration = trajectory.back().timestamp - trajectory.front().timestamp;
  if (s.duration <= 1.0) return s;
  std::vector<double> translation, rotation;
  std::size_t j = 0;
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    // The pose whose stamp is closest to one second later (TUM's statistics: delta = 1 s).
    const double target = trajectory[i].timestamp + 1.0;
    if (target > trajectory.back().timestamp) break;
    j = std::max(j, i);
    while (j + 1 < trajectory.size() &&
           std::abs(trajectory[j + 1].timestamp - target) <= std::abs(trajectory[j].timestamp - target))
      ++j;
    const Eigen::Isometry3d motion = trajectory[i].pose.inverse() * trajectory[j].pose;
    translation.push_back(motion.translation().norm());
    const double c = std::clamp((motion.linear().trace() - 1.0) / 2.0, -1.0, 1.0);
    rotation.push_back(std::acos(c));
  }
  if (translation.empty()) return s;
  double sum_t = 0.0, sum_r = 0.0;
  for (double t : translation) sum_t += t;
  for (double r : rotation) sum_r += r;
  const double rate = (static_cast<double>(trajectory.size()) - 1.0) / s.duration;
  s.mean_speed = sum_t / static_cast<double>(translation.size());
  s.mean_angular_speed = sum_r / static_cast<double>(rotation.size()) * 180.0 / M_PI;
  s.length = sum_t / rate;
  return s;
}

}  // namespace lrd::eval
