#pragma once
// Keyframe culling (ORB-SLAM2's KeyFrameCulling, paper §2.2) with a second rule for a camera that
// keeps coming back to the same place (bench/results/scale.md: the map should grow with the
// explored space, not with the time spent in it).
//
// ORB-SLAM2's rule removes a keyframe when 90 % of its close points are seen by three other
// keyframes at the same or a finer scale. Lap after lap around one room, people hide and reveal
// background, and each keyframe a revisit makes creates points for what it saw between them
// (scale.md, walking_circle): it never reaches 90 %, and the map grew by a keyframe or two a lap.
// The place rule removes such a keyframe when a keyframe made well before it (the camera went away
// and came back) stands at the same place — a baseline that is a small share of the scene depth,
// the view turned by a few degrees, so the two views hold nearly the same information — shares
// points with it, and a looser share of its points is seen by three others. The older keyframe
// stays, so the map keeps the first view of a place. A camera that stays in one place (hand-held
// back and forth) is left to ORB-SLAM2's rule: culling there cost accuracy on the short presets.
#include <cstdint>

namespace lrd::map {
class KeyFrame;
}
namespace lrd::mapping {

struct KeyFrameCullingParams {
  double redundant_ratio = 0.9;  // a keyframe goes when this share of its close points ...
  int redundant_observers = 3;   // ... is seen by this many other keyframes at a similar scale
  // The place rule (0: off): a good covisible keyframe made `place_keyframes_apart` or more
  // keyframes earlier, within `place_baseline_ratio` of the median scene depth and
  // `place_angle_deg` between the optical axes, and this share of the points seen by three others.
  double place_redundant_ratio = 0.5;
  double place_baseline_ratio = 0.045;
  double place_angle_deg = 7.0;
  // Judged only once this many keyframes have been made after it, too: while the camera is still
  // there, the points it saw between people are what tracking holds on to (walking_circle, frame
  // 1,087: culling the last two cost 2.8 cm).
  int place_keyframes_apart = 10;
};

struct Redundancy {
  int close_points = 0;  // good map points of close keypoints (RGB-D: far ones are weakly constrained)
  int redundant = 0;     // of those, seen by `redundant_observers` others at the same or a finer scale
};

[[nodiscard]] Redundancy redundancy(const map::KeyFrame& kf, int observers);

// The most covisible good keyframe made `place_keyframes_apart` or more keyframes before `kf` and
// standing at `kf`'s place (above); nullptr if none.
[[nodiscard]] const map::KeyFrame* older_keyframe_at_same_place(const map::KeyFrame& kf,
                                                                const KeyFrameCullingParams& params);

struct CullingDecision {
  bool cull = false;
  Redundancy points;
  const map::KeyFrame* same_place = nullptr;  // set when the place rule decided
};

// Either rule, judged when keyframe `newest_id` is being mapped. The caller holds the map mutex.
[[nodiscard]] CullingDecision judge_redundancy(const map::KeyFrame& kf, std::uint64_t newest_id,
                                               const KeyFrameCullingParams& params);

}  // namespace lrd::mapping
