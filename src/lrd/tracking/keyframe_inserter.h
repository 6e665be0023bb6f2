#pragma once
// The keyframe decision (ORB-SLAM2's NeedNewKeyFrame / CreateNewKeyFrame, RGB-D, with our
// keyframe-coverage rule, docs/slam-core.md): after a frame is tracked, whether it becomes a
// keyframe, and if so the keyframe with new map points from its depth, handed to local mapping.
#include <cstddef>
#include <cstdint>
#include <optional>

#include "lrd/tracking/tracker_params.h"

namespace lrd::data {
class Frame;
}
namespace lrd::map {
class KeyFrame;
class Map;
class MapPoint;
}  // namespace lrd::map
namespace lrd::mapping {
class LocalMapper;
}

namespace lrd::tracking {

// A new map point at keypoint i's depth, observed by `kf` alone, set as the frame's match (the
// RGB-D way to make points: map initialization and new keyframes). Null without depth.
map::MapPoint* add_point_from_depth(map::Map& map, map::KeyFrame* kf, data::Frame& frame, std::size_t i);

// What the decision needs to know about tracking's state.
struct KeyFrameContext {
  const map::KeyFrame* reference = nullptr;   // the frame's reference keyframe
  int inliers = 0;                            // map points tracked in the frame
  std::optional<std::uint64_t> recovered_at;  // frame id of the last recovery from loss
};

class KeyFrameInserter {
 public:
  KeyFrameInserter(map::Map& map, mapping::LocalMapper& mapper, const TrackerParams& params)
      : map_(map), mapper_(mapper), params_(params) {}

  // Map mutex held. May interrupt local mapping's BA to make room for the keyframe.
  [[nodiscard]] bool needed(const data::Frame& frame, const KeyFrameContext& context) const;
  // Makes `frame` a keyframe with new map points from its close depths (map mutex held) and
  // queues it for local mapping.
  map::KeyFrame* insert(data::Frame& frame);
  // The first keyframe was made from `frame` (map initialization).
  void inserted_first(const data::Frame& frame);

 private:
  map::Map& map_;
  mapping::LocalMapper& mapper_;
  const TrackerParams& params_;
  std::uint64_t last_keyframe_frame_id_ = 0;
};

}  // namespace lrd::tracking
