#pragma once
// What tracking keeps of every frame: its pose relative to the reference keyframe, so the
// trajectory follows later corrections of the map.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>

#include "lrd/tracking/tracking_state.h"

namespace lrd::tracking {

// One tracked (or lost) frame: its pose relative to the reference keyframe.
struct FrameRecord {
  std::uint64_t frame_id = 0;
  double timestamp = 0.0;
  TrackingState state = TrackingState::NotInitialized;
  // The reference keyframe's id (it may be culled and freed since: Map::resolve_pose follows it).
  std::optional<std::uint64_t> reference;
  Eigen::Isometry3d T_c_ref = Eigen::Isometry3d::Identity();
  int inliers = 0;
};

}  // namespace lrd::tracking
