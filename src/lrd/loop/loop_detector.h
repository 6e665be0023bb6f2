#pragma once
// Loop detection (ORB-SLAM2's LoopClosing::DetectLoop and ComputeSim3, RGB-D: SE(3)), paper §2.2:
//  1. candidates: keyframes not covisible with the new one whose bag-of-words score beats the
//     lowest score of the new keyframe's covisible neighbours (keyframe database, group scores);
//  2. consistency: a candidate counts only once its covisibility group has been a candidate for
//     3 consecutive keyframes, so one-off look-alikes do not close loops;
//  3. geometry: BoW matches between the two keyframes' map points, a rigid transform by RANSAC,
//     then the candidate's neighbourhood projected at the corrected pose for more matches; a loop
//     needs at least `min_matches` of them.
// A loop may also be suggested (LoopCloser::suggest_loop: tracking relocalized beyond where the
// camera can have gone, the map holding the place twice); verify_suggested checks it.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <set>
#include <vector>

#include "lrd/config/node_reader.h"
#include "lrd/map/by_id.h"

namespace lrd::map {
class KeyFrame;
class KeyFrameDatabase;
class MapPoint;
}  // namespace lrd::map

namespace lrd::loop {

struct LoopDetectorParams {
  int consistency = 3;             // consecutive keyframes a candidate group must persist
  int min_keyframes_between = 10;  // no new loop within this many keyframes of the last one
  int min_bow_matches = 20;
  int min_ransac_inliers = 20;
  int min_matches = 40;  // after the projection search
  int ransac_iterations = 300;
};

struct LoopDetection {
  map::KeyFrame* current = nullptr;
  map::KeyFrame* loop = nullptr;
  Eigen::Isometry3d T_cw_corrected = Eigen::Isometry3d::Identity();  // current keyframe, in the loop's map
  std::vector<map::MapPoint*> matches;      // per current keypoint: the loop side's map point
  std::vector<map::MapPoint*> loop_points;  // the loop keyframe's neighbourhood
  int ransac_inliers = 0;
  int match_count = 0;
};

class LoopDetector {
 public:
  LoopDetector(map::KeyFrameDatabase& database, LoopDetectorParams params);
  // Call under Map::mutex() with each new keyframe (BoW computed), in keyframe order.
  std::optional<LoopDetection> detect(map::KeyFrame* kf);
  // A loop suggested from outside: `kf` is on the map the camera left, `T_cw_guess` where
  // `candidate`'s map puts it. Verified as a detected loop is, the consistency over keyframes
  // aside (the relocalization that suggested it stands for that): the candidate's neighbourhood
  // projected into `kf` at the guess, the pose refined by motion-only BA on those matches with
  // at least `min_ransac_inliers` inliers, projected again; `min_matches` inliers needed.
  [[nodiscard]] std::optional<LoopDetection> verify_suggested(map::KeyFrame* kf, map::KeyFrame* candidate,
                                                              const Eigen::Isometry3d& T_cw_guess) const;
  // After a loop was closed at `kf`: the next loop waits min_keyframes_between keyframes.
  void loop_closed(const map::KeyFrame* kf);
  // A loop was closed at `kf` or at a keyframe after it (a suggestion for `kf` is then stale).
  [[nodiscard]] bool closed_since(const map::KeyFrame* kf) const;

 private:
  struct ConsistentGroup {
    std::set<std::uint64_t> keyframes;  // ids: a keyframe may be removed and freed meanwhile
    int consistency = 0;
  };
  std::vector<map::KeyFrame*> consistent_candidates(const std::vector<map::KeyFrame*>& candidates);
  std::optional<LoopDetection> verify(map::KeyFrame* kf, map::KeyFrame* candidate) const;

  map::KeyFrameDatabase& database_;
  LoopDetectorParams params_;
  std::vector<ConsistentGroup> groups_;
  std::uint64_t last_loop_kf_ = 0;
  bool any_loop_ = false;
};

}  // namespace lrd::loop
