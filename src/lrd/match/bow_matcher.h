#pragma once
// Descriptor matching guided by the vocabulary (ORB-SLAM2's SearchByBoW): two views' keypoints
// are compared only when they fall under the same vocabulary node (the direct index,
// Frame::bow_features), which makes matching against a keyframe cheap enough for relocalization
// and loop detection, where no pose is known to guide a projection search.
#include <cstddef>
#include <vector>

#include "lrd/match/orb_matcher.h"

namespace lrd::map {
class KeyFrame;
class MapPoint;
}  // namespace lrd::map
namespace lrd::data {
class Frame;
}

namespace lrd::match {

class BowMatcher {
 public:
  explicit BowMatcher(MatcherParams params = {0.75f, true}) : params_(params) {}

  // The keyframe's map points matched to the frame's keypoints: out[frame keypoint] = map point
  // (nullptr: none). Both need their BoW. Returns the number of matches.
  int match(const map::KeyFrame& kf, const data::Frame& frame, std::vector<map::MapPoint*>& out) const;
  // Between two keyframes' map points: out[kf1 keypoint] = kf2's map point.
  int match(const map::KeyFrame& kf1, const map::KeyFrame& kf2, std::vector<map::MapPoint*>& out) const;

 private:
  MatcherParams params_;
};

}  // namespace lrd::match
