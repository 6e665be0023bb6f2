#pragma once
// How far the camera went over the last moment of unbroken tracking (docs/slam-core.md, "Moving
// faster than a camera"): a tracker whose matches are dominated by a person walking past follows
// the person, at a walking pace no hand-held or indoor robot camera keeps, until the map no longer
// agrees and tracking is lost far from where the camera is (a static-mode walking_halfsphere run
// went 0.6 m in 10 frames against 7 cm in truth, then relocalized 0.67 m back). Measured over a few
// frames, not one, so the frame-to-frame jitter of tracking among people averages out.
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "lrd/tracking/frame_record.h"

namespace lrd::map {
class Map;
}

namespace lrd::tracking {

struct CameraStride {
  double metres = 0.0;                // straight-line distance between the two camera centres
  double seconds = 0.0;               // between their stamps
  const FrameRecord* from = nullptr;  // where it began (in the records passed)
  Eigen::Vector3d from_t_wc = Eigen::Vector3d::Zero();
  [[nodiscard]] double speed() const { return metres / seconds; }
};

// The camera centre of a tracked frame, where its reference keyframe stands now. Map mutex held.
[[nodiscard]] Eigen::Vector3d recorded_centre(const FrameRecord& record, const map::Map& map);

// From the oldest frame tracked within `window` seconds before `timestamp`, with no lost frame
// since, to a camera centre `t_wc` at `timestamp`; each earlier frame placed where its reference
// keyframe stands now (so a loop correction meanwhile is not a stride). Empty when that spans
// less than `min_seconds` (just after a loss, or the first frames). Map mutex held.
[[nodiscard]] std::optional<CameraStride> recent_stride(const std::vector<FrameRecord>& records,
                                                        const map::Map& map, double timestamp,
                                                        const Eigen::Vector3d& t_wc, double window,
                                                        double min_seconds);

}  // namespace lrd::tracking
