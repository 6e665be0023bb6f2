#pragma once
// Camera tracking (ORB-SLAM2's Tracking, RGB-D; paper §2.2): initialises the map from the first
// frame with enough depth, then for each frame estimates the pose from a constant-velocity motion
// model (falling back to matching the reference keyframe), refines it against the local map
// (covisible keyframes and their points), and decides when a new keyframe is needed. Every
// frame's pose is stored relative to its reference keyframe, so the trajectory follows later
// corrections of the map.
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "lrd/config/node_reader.h"
#include "lrd/data/frame.h"
#include "lrd/match/orb_matcher.h"
#include "lrd/optim/pose_optimizer.h"
#include "lrd/tracking/tracking_state.h"

namespace lrd::map {
class KeyFrame;
class Map;
class MapPoint;
}  // namespace lrd::map
namespace lrd::mapping {
class LocalMapper;
}
namespace lrd::place {
class KeyFrameDatabase;
class Vocabulary;
}  // namespace lrd::place

namespace lrd::tracking {

struct TrackerParams {
  int init_min_features = 500;          // keypoints with depth needed to start the map
  float motion_model_radius = 15.0f;    // search radius (px at level 0), ORB-SLAM2's RGB-D value
  int min_motion_matches = 20;          // below: widen the search once, then fall back
  int min_reference_matches = 15;       // reference-keyframe matching
  int min_pose_inliers = 10;            // after motion-only optimization
  int min_local_map_inliers = 30;       // tracking is OK above this
  int min_inliers_after_recovery = 50;  // ... for a second after recovering from loss
  int max_local_keyframes = 80;
  float local_map_radius = 1.0f;
  int max_frames_between_keyframes = 0;  // 0: the camera's fps
  int min_frames_between_keyframes = 0;
  double reference_ratio = 0.75;  // keyframe when tracked points fall below this share of the reference's
  int keyframe_close_points = 100;      // new keyframes create points from at least this many close depths
  // Keyframe when the tracked close points span less than this share of the extent of all close
  // keypoints, across or down the image: a map seen in one strip of the view leaves rotation and
  // sideways translation nearly interchangeable (0: off, as ORB-SLAM2; docs/slam-core.md).
  double keyframe_coverage = 0.7;
  int min_relocalization_inliers = 20;  // after motion-only BA on the PnP inliers
  optim::PoseOptimizerParams pose;

  // Reads the `tracking` section of the config (and finishes it).
  static TrackerParams from_config(config::NodeReader reader);
};

// One tracked (or lost) frame: its pose relative to the reference keyframe.
struct FrameRecord {
  std::uint64_t frame_id = 0;
  double timestamp = 0.0;
  TrackingState state = TrackingState::NotInitialized;
  map::KeyFrame* reference = nullptr;
  Eigen::Isometry3d T_c_ref = Eigen::Isometry3d::Identity();
  int inliers = 0;
};

class Tracker {
 public:
  Tracker(map::Map& map, mapping::LocalMapper& mapper, TrackerParams params);

  // Tracks `frame` (features already extracted), holding the map mutex meanwhile; `wait_seconds`
  // receives the time spent waiting for that mutex (local mapping holding it).
  TrackingState track(data::Frame& frame, double* wait_seconds = nullptr);

  // Called once per frame after the first pose estimate (motion model or reference keyframe) and
  // before local-map tracking, with the map mutex held and the keyframes near the frame: the
  // multi-view geometry check (paper §2.7) removes the dynamic keypoints it finds there, so the
  // final pose is optimized without them and they never create map points.
  using DynamicCheck = std::function<void(data::Frame& frame, const std::vector<map::KeyFrame*>& nearby)>;
  void set_dynamic_check(DynamicCheck check) { dynamic_check_ = std::move(check); }
  // Relocalization when lost (without: only the last reference keyframe is tried again).
  void set_place_recognition(const place::Vocabulary* vocabulary, place::KeyFrameDatabase* database) {
    vocabulary_ = vocabulary;
    database_ = database;
  }
  // Frames relocalized so far.
  [[nodiscard]] int relocalizations() const { return relocalizations_; }

  // World-to-camera pose of the next frame by the constant-velocity model (empty when not
  // tracking). Map mutex not needed: it reads the tracker's own state only; call between frames.
  [[nodiscard]] std::optional<Eigen::Isometry3d> predicted_pose() const;

  [[nodiscard]] TrackingState state() const { return state_; }
  [[nodiscard]] const std::vector<FrameRecord>& records() const { return records_; }
  [[nodiscard]] const TrackerParams& params() const { return params_; }

 private:
  void initialize(data::Frame& frame);
  bool track_reference_keyframe(data::Frame& frame);
  bool relocalize(data::Frame& frame);  // relocalization.cc
  bool track_with_motion_model(data::Frame& frame);
  bool track_local_map(data::Frame& frame);
  void update_local_keyframes(data::Frame& frame);
  void update_local_points(const data::Frame& frame);
  int search_local_points(data::Frame& frame);
  bool in_frustum(const data::Frame& frame, map::MapPoint* mp, float view_cos_limit) const;
  int optimize_pose(data::Frame& frame);
  [[nodiscard]] bool need_new_keyframe(const data::Frame& frame) const;
  void create_new_keyframe(data::Frame& frame);
  void update_last_frame();
  [[nodiscard]] bool recently_recovered(const data::Frame& frame) const;

  map::Map& map_;
  mapping::LocalMapper& mapper_;
  TrackerParams params_;
  match::OrbMatcher motion_matcher_;  // nn 0.9, rotation check
  match::OrbMatcher reference_matcher_;  // nn 0.7, rotation check
  match::OrbMatcher local_matcher_;      // nn 0.8

  TrackingState state_ = TrackingState::NotInitialized;
  std::optional<data::Frame> last_frame_;
  map::KeyFrame* last_frame_reference_ = nullptr;
  Eigen::Isometry3d last_T_c_ref_ = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Isometry3d> velocity_;  // T_c(t) c(t-1)
  map::KeyFrame* reference_kf_ = nullptr;
  std::uint64_t last_keyframe_frame_id_ = 0;
  std::uint64_t recovered_frame_id_ = 0;
  bool recovered_ = false;
  int inliers_ = 0;
  std::vector<map::KeyFrame*> local_keyframes_;
  std::vector<map::MapPoint*> local_points_;
  std::vector<FrameRecord> records_;
  DynamicCheck dynamic_check_;
  const place::Vocabulary* vocabulary_ = nullptr;
  place::KeyFrameDatabase* database_ = nullptr;
  int relocalizations_ = 0;
};

}  // namespace lrd::tracking
