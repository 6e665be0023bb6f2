#include "lrd/optim/odometry_change.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "lrd/map/keyframe.h"

namespace lrd::optim {

MotionSize motion_size(const Eigen::Isometry3d& T) {
  return {T.translation().norm(), Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI};
}

OdometryChange largest_odometry_change(const std::vector<map::KeyFrame*>& keyframes, const PoseOf& before,
                                       const PoseOf& after,
                                       const std::function<bool(const map::KeyFrame*)>& counted) {
  std::unordered_map<std::uint64_t, map::KeyFrame*> by_id;
  for (map::KeyFrame* k : keyframes) by_id.emplace(k->id(), k);
  OdometryChange worst;
  const auto measure = [&](map::KeyFrame* k, map::KeyFrame* other, const Eigen::Isometry3d* tracked) {
    if (other == nullptr || other->is_bad()) return;
    if (counted && (!counted(k) || !counted(other))) return;
    const Eigen::Isometry3d rel_before = before(k) * before(other).inverse();
    const Eigen::Isometry3d rel_after = after(k) * after(other).inverse();
    const auto [metres, degrees] = motion_size(rel_before.inverse() * rel_after);
    if (metres > worst.metres) {
      worst.keyframe = k->id();
      worst.other = other->id();
    }
    worst.metres = std::max(worst.metres, metres);
    worst.degrees = std::max(worst.degrees, degrees);
    if (tracked == nullptr) return;
    // Further from the tracked odometry than before: by a millimetre or a twentieth of a degree
    // (a solver's noise on a pair it leaves alone is not a step away).
    const auto [was_m, was_deg] = motion_size(tracked->inverse() * rel_before);
    const auto [now_m, now_deg] = motion_size(tracked->inverse() * rel_after);
    if (now_m <= was_m + 1e-3 && now_deg <= was_deg + 0.05) return;
    if (now_m > worst.from_tracked_metres) {
      worst.from_tracked_keyframe = k->id();
      worst.from_tracked_other = other->id();
    }
    worst.from_tracked_metres = std::max(worst.from_tracked_metres, now_m);
    worst.from_tracked_degrees = std::max(worst.from_tracked_degrees, now_deg);
  };
  for (map::KeyFrame* k : keyframes) {
    if (k->is_bad()) continue;
    measure(k, k->parent(), nullptr);
    for (const auto& [id, tracked] : k->tracking_links()) {
      const auto it = by_id.find(id);
      if (id > k->id() && it != by_id.end()) measure(k, it->second, &tracked);  // each pair once
    }
  }
  return worst;
}

std::string OdometryChange::beyond(double max_metres, double max_degrees) const {
  if (metres > max_metres || degrees > max_degrees)
    return fmt::format("move keyframe {} by {:.3f} m / {:.1f} deg against keyframe {}", keyframe, metres,
                       degrees, other);
  return fmt::format(
      "take keyframe {} {:.3f} m / {:.1f} deg from its odometry with keyframe {} as tracked, {}",
      from_tracked_keyframe, from_tracked_metres, from_tracked_degrees, from_tracked_other,
      "corrections added up");
}

Fallback fall_back_if_torn(const std::vector<map::KeyFrame*>& keyframes, const PoseOf& before,
                           SolvedPoses& solution, const SolvedPoses& fallback, double max_metres,
                           double max_degrees) {
  Fallback f;
  f.change =
      largest_odometry_change(keyframes, before, [&](map::KeyFrame* k) { return solution.at(k->id()); });
  if (f.change.within(max_metres, max_degrees)) return f;
  f.taken = true;
  take_solution(solution, fallback);
  return f;
}

void take_solution(SolvedPoses& solution, const SolvedPoses& other) {
  for (auto& [id, T_cw] : solution)
    if (const auto it = other.find(id); it != other.end()) T_cw = it->second;
}

}  // namespace lrd::optim
