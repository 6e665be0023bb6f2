#include "lrd/optim/odometry_change.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "lrd/map/keyframe.h"

namespace lrd::optim {

OdometryChange largest_odometry_change(const std::vector<map::KeyFrame*>& keyframes, const PoseOf& before,
                                       const PoseOf& after,
                                       const std::function<bool(const map::KeyFrame*)>& counted) {
  std::unordered_map<std::uint64_t, map::KeyFrame*> by_id;
  for (map::KeyFrame* k : keyframes) by_id.emplace(k->id(), k);
  OdometryChange worst;
  const auto measure = [&](map::KeyFrame* k, map::KeyFrame* other) {
    if (other == nullptr || other->is_bad()) return;
    if (counted && (!counted(k) || !counted(other))) return;
    const Eigen::Isometry3d rel_before = before(k) * before(other).inverse();
    const Eigen::Isometry3d rel_after = after(k) * after(other).inverse();
    const Eigen::Isometry3d change = rel_before.inverse() * rel_after;
    const double metres = change.translation().norm();
    const double degrees = Eigen::AngleAxisd(change.linear()).angle() * 180.0 / M_PI;
    if (metres > worst.metres) {
      worst.keyframe = k->id();
      worst.other = other->id();
    }
    worst.metres = std::max(worst.metres, metres);
    worst.degrees = std::max(worst.degrees, degrees);
  };
  for (map::KeyFrame* k : keyframes) {
    if (k->is_bad()) continue;
    measure(k, k->parent());
    for (const std::uint64_t id : k->tracking_links()) {
      const auto it = by_id.find(id);
      if (id > k->id() && it != by_id.end()) measure(k, it->second);  // each pair once
    }
  }
  return worst;
}

Fallback fall_back_if_torn(const std::vector<map::KeyFrame*>& keyframes, const PoseOf& before,
                           SolvedPoses& solution, const SolvedPoses& fallback, double max_metres,
                           double max_degrees) {
  Fallback f;
  f.change =
      largest_odometry_change(keyframes, before, [&](map::KeyFrame* k) { return solution.at(k->id()); });
  if (f.change.metres <= max_metres && f.change.degrees <= max_degrees) return f;
  f.taken = true;
  for (auto& [id, T_cw] : solution)
    if (const auto it = fallback.find(id); it != fallback.end()) T_cw = it->second;
  return f;
}

}  // namespace lrd::optim
