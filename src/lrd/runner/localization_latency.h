#pragma once
// How soon a run placed itself in a loaded map (map files, docs/map-files.md): the first frame it
// tracked, against the first frame whose view held mapped structure. A frame "sees the map" when at
// least `min_points` of the loaded map's points lie in front of its true camera (the ground-truth
// pose, brought into the map's frame by the run's own ATE alignment), project inside the image, and
// are not hidden: the frame's measured depth at that pixel is within 10 % of the point's depth.
#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <vector>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/io/frame_source.h"
#include "lrd/io/trajectory.h"
#include "lrd/tracking/tracking_state.h"

namespace lrd::runner {

struct LocalizationLatency {
  std::optional<std::size_t> first_localized_frame;  // run's frame index
  std::optional<std::size_t> first_view_frame;       // run's frame index
  // Frames from the first view to the first localized one (0 when localized at once or before).
  [[nodiscard]] std::optional<std::size_t> frames() const {
    if (!first_localized_frame || !first_view_frame) return std::nullopt;
    return *first_localized_frame > *first_view_frame ? *first_localized_frame - *first_view_frame : 0;
  }
};

// `states`: each frame's tracking state, in run order. `ground_truth_from_map` maps the run's
// (= the map's) frame onto the ground truth's. Reads depth from `source` only up to the first view.
[[nodiscard]] LocalizationLatency localization_latency(const std::vector<Eigen::Vector3d>& map_points,
                                                       const std::vector<tracking::TrackingState>& states,
                                                       const io::FrameSource& source,
                                                       const io::Trajectory& ground_truth,
                                                       const Eigen::Isometry3d& ground_truth_from_map,
                                                       const camera::PinholeCamera& camera,
                                                       std::size_t min_points = 50);

}  // namespace lrd::runner
