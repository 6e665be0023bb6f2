#pragma once
// What tracking needs from the dynamic front end, and nothing more: after the first pose estimate
// of a frame and before it is refined against the local map, the keypoints on moving objects are
// found and removed (paper §2.7), so they never reach the final pose or the map.
#include <vector>

namespace lrd::data {
class Frame;
}
namespace lrd::map {
class KeyFrame;
}

namespace lrd::dynamic {

// What the multi-view geometry check did with one frame.
struct GeometryStats {
  int keypoints_removed = 0;  // keypoints of the frame judged dynamic and removed
  int seeds = 0;              // projected points found moving
  double seconds = 0.0;
};

class MovingPointCheck {
 public:
  virtual ~MovingPointCheck() = default;
  // `frame` has its first pose estimate; `nearby` are the keyframes around it. The map mutex is
  // held. Removes the frame's dynamic keypoints and adds the moving pixels to its dynamic mask.
  virtual GeometryStats remove_moving_points(data::Frame& frame,
                                             const std::vector<map::KeyFrame*>& nearby) = 0;
};

}  // namespace lrd::dynamic
