#pragma once
// How much a solution (a pose graph's, a global BA's) changes the map's odometry: each keyframe's
// pose relative to its spanning-tree parent, and relative to the keyframes it is tracking-linked
// to (consecutive frames were tracked against the two: the camera trajectory passes from one to
// the other between two frames), after against before. Odometry between keyframes a fraction of
// a second apart is never wrong by decimetres, so a solution that changes one such pair that much
// has not spread a drift but torn the map, and the camera trajectory would jump there
// (the divergence hunt, bench/results/divergence.md).
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace lrd::map {
class KeyFrame;
}

namespace lrd::optim {

// World-to-camera pose of a keyframe under one solution (or before it).
using PoseOf = std::function<Eigen::Isometry3d(map::KeyFrame*)>;

// The size of a rigid motion: its translation and its rotation angle.
struct MotionSize {
  double metres = 0.0;
  double degrees = 0.0;
  [[nodiscard]] bool within(double max_metres, double max_degrees) const {
    return metres <= max_metres && degrees <= max_degrees;
  }
};
[[nodiscard]] MotionSize motion_size(const Eigen::Isometry3d& T);

struct OdometryChange {
  double metres = 0.0;
  double degrees = 0.0;
  std::uint64_t keyframe = 0;  // the pair whose relative position changed most: this keyframe
  std::uint64_t other = 0;     // ... and its parent or linked keyframe
  // Corrections add up: of the tracking-linked pairs the solution takes further from their odometry
  // as tracked (KeyFrame::tracking_links) than they were, how far the furthest ends up. A pair
  // brought back towards it is never held against a solution (that mends a tear).
  double from_tracked_metres = 0.0;
  double from_tracked_degrees = 0.0;
  std::uint64_t from_tracked_keyframe = 0;
  std::uint64_t from_tracked_other = 0;

  // Both measures within the limits.
  [[nodiscard]] bool within(double max_metres, double max_degrees) const {
    return metres <= max_metres && degrees <= max_degrees && from_tracked_metres <= max_metres &&
           from_tracked_degrees <= max_degrees;
  }
  // For a warning: what went beyond `within`'s limits ("would ..." follows it), e.g. "move
  // keyframe 5 by 0.300 m / 4.0 deg against keyframe 4".
  [[nodiscard]] std::string beyond(double max_metres, double max_degrees) const;
};

// Over the pairs among `keyframes` (bad ones skipped; with `counted`, only pairs of which it
// accepts both): each with its parent, and with each keyframe it is tracking-linked to.
[[nodiscard]] OdometryChange largest_odometry_change(
    const std::vector<map::KeyFrame*>& keyframes, const PoseOf& before, const PoseOf& after,
    const std::function<bool(const map::KeyFrame*)>& counted = {});

// Poses of one solution by keyframe id (as optim::PoseGraphResult::T_cw holds them).
using SolvedPoses = std::map<std::uint64_t, Eigen::Isometry3d>;

struct Fallback {
  OdometryChange change;  // of the solution judged
  bool taken = false;     // it went beyond the limits and the fallback replaced it
};

// `other`'s poses in place of `solution`'s (poses `other` lacks stay).
void take_solution(SolvedPoses& solution, const SolvedPoses& other);

// `solution`, or, when it changes the odometry of `keyframes` (against `before`) beyond the limits,
// the `fallback` solution's poses in its place (poses the fallback lacks stay): the loop
// correction's real solve and its dry run (loop_closer.cc).
Fallback fall_back_if_torn(const std::vector<map::KeyFrame*>& keyframes, const PoseOf& before,
                           SolvedPoses& solution, const SolvedPoses& fallback, double max_metres,
                           double max_degrees);

}  // namespace lrd::optim
