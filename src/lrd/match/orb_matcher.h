#pragma once
// ORB descriptor matching between frames, keyframes and map points (ORB-SLAM2's ORBmatcher,
// RGB-D cases): Hamming distance with thresholds, Lowe's ratio test, the rotation-consistency
// histogram, and searches guided by projection with a radius that grows with the pyramid level.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <utility>
#include <vector>

#include "lrd/data/frame.h"

namespace lrd::map {
class KeyFrame;
class MapPoint;
}  // namespace lrd::map

namespace lrd::match {

struct MatcherParams {
  float nn_ratio = 0.6f;          // best / second-best distance must be below this
  bool check_orientation = true;  // rotation-consistency histogram
};

class OrbMatcher {
 public:
  static constexpr int kThHigh = 100;  // accept a guided match up to this distance
  static constexpr int kThLow = 50;    // accept an unguided match up to this distance

  explicit OrbMatcher(MatcherParams params = {}) : params_(params) {}

  // Motion model: projects the last frame's (inlier) map points into `current` at its predicted
  // pose and matches within th * scale radius, on levels consistent with the forward/backward
  // motion. Writes current.map_points; returns the number of matches.
  int search_by_projection(data::Frame& current, const data::Frame& last, float th) const;

  // Local map: matches the points flagged in view (MapPoint::track.in_view, projected by the
  // caller) to unmatched keypoints of `current`; radius th * (2.5 | 4 by viewing angle) * scale.
  int search_by_projection(data::Frame& current, const std::vector<map::MapPoint*>& points, float th) const;

  // Loop closing: projects `points` into `kf` at the pose `T_cw` (the loop-corrected one, not the
  // keyframe's own) and matches them to keypoints without an entry in `matched` (one slot per kf
  // keypoint; filled here). Radius th * scale; distance up to kThLow. Returns new matches.
  int search_by_projection(const map::KeyFrame& kf, const Eigen::Isometry3d& T_cw,
                           const std::vector<map::MapPoint*>& points, std::vector<map::MapPoint*>& matched,
                           float th) const;
  // Reference keyframe: nearest-neighbour descriptor matching of the keyframe's map points
  // against all keypoints of `current` (ratio test, kThLow, rotation check). No pose needed.
  int search_by_descriptor(const map::KeyFrame& kf, data::Frame& current) const;

  // Triangulation candidates between two keyframes: keypoints without a map point in both,
  // consistent with the epipolar geometry (F12 maps kf2 points to lines in kf1, x1' F12 x2 = 0).
  // Returns (index in kf1, index in kf2) pairs.
  [[nodiscard]] std::vector<std::pair<std::size_t, std::size_t>> search_for_triangulation(
      map::KeyFrame& kf1, map::KeyFrame& kf2, const Eigen::Matrix3d& F12) const;

  // Duplicate fusion: projects `points` into `kf`; a point matching a keypoint that already has
  // a map point is merged with it (the one with more observations survives), otherwise it gains
  // the observation. Returns the number of fused or added points.
  int fuse(map::KeyFrame& kf, const std::vector<map::MapPoint*>& points, float th = 3.0f) const;

 private:
  MatcherParams params_;
};

}  // namespace lrd::match
