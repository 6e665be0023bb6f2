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
#include <utility>
#include <vector>

#include "lrd/data/frame.h"
#include "lrd/dynamic/moving_point_check.h"
#include "lrd/map/reclamation.h"
#include "lrd/match/orb_matcher.h"
#include "lrd/tracking/frame_record.h"
#include "lrd/tracking/keyframe_inserter.h"
#include "lrd/tracking/local_map.h"
#include "lrd/tracking/motion_model.h"
#include "lrd/tracking/tracker_params.h"
#include "lrd/tracking/tracking_state.h"

namespace lrd::map {
class KeyFrame;
class KeyFrameDatabase;
class Map;
class MapPoint;
}  // namespace lrd::map
namespace lrd::mapping {
class LocalMapper;
}
namespace lrd::place {
class Vocabulary;
}

namespace lrd::tracking {

// Everything tracking did with one frame: callers never read the tracker's internals to learn it.
struct TrackOutcome {
  TrackingState state = TrackingState::NotInitialized;
  std::optional<Eigen::Isometry3d> T_cw;  // world-to-camera, when tracking is OK
  int inliers = 0;                        // map points matched and kept by the pose optimization
  map::KeyFrame* new_keyframe = nullptr;  // the keyframe this frame became (also the first one)
  // ... read under the map mutex, for callers that must not take it: its id, pose (camera-to-
  // world) and the map points it observes.
  std::uint64_t new_keyframe_id = 0;
  Eigen::Isometry3d new_keyframe_T_wc = Eigen::Isometry3d::Identity();
  std::size_t new_keyframe_points = 0;
  bool relocalized = false;         // recovered from loss on this frame by place recognition
  dynamic::GeometryStats geometry;  // the moving-point check (zero without one)
  double wait_seconds = 0.0;        // waiting for local mapping to release the map
  // The local map the frame was tracked against (keyframes, map points), when tracked.
  std::size_t local_keyframes = 0, local_points = 0;
};

// Tracking relocalized, a brief loss after it was last tracked against keyframe `lost_keyframe_id`,
// against `found_keyframe_id` where the camera cannot have gone meanwhile: the map may hold the
// place twice. `T_cw_lost_keyframe` puts the lost keyframe where the relocalization says the
// camera is (Tracker::suggest_crossing; the loop closer verifies it, LoopCloser::suggest_loop).
struct MapCrossing {
  std::uint64_t lost_keyframe_id = 0;
  std::uint64_t found_keyframe_id = 0;
  Eigen::Isometry3d T_cw_lost_keyframe = Eigen::Isometry3d::Identity();
};

class Tracker {
 public:
  Tracker(map::Map& map, mapping::LocalMapper& mapper, TrackerParams params);

  // Tracks `frame` (features already extracted), holding the map mutex meanwhile.
  TrackOutcome track(data::Frame& frame);

  // Called once per frame after the first pose estimate (motion model or reference keyframe) and
  // before local-map tracking, with the map mutex held and the keyframes near the frame: the
  // multi-view geometry check (paper §2.7) removes the dynamic keypoints it finds there, so the
  // final pose is optimized without them and they never create map points. Null: no check.
  void set_moving_point_check(dynamic::MovingPointCheck* check) { moving_point_check_ = check; }
  // Relocalization when lost (without: only the last reference keyframe is tried again).
  void set_place_recognition(const place::Vocabulary* vocabulary, map::KeyFrameDatabase* database) {
    vocabulary_ = vocabulary;
    database_ = database;
  }
  // Where each map crossing goes (called in the tracking thread, map mutex held); none: dropped.
  using CrossingCallback = std::function<void(const MapCrossing&)>;
  void set_crossing_callback(CrossingCallback callback) { crossing_callback_ = std::move(callback); }
  // A map was loaded (map/map_file.h): frames relocalize against it until one is placed, instead
  // of starting a new map. Call before the first frame.
  void start_in_loaded_map() { state_ = TrackingState::NotLocalized; }
  // Localization only (docs/map-files.md): track against the map without adding keyframes (so no map
  // points either; local mapping and loop closing stay idle).
  void set_localization_only(bool on) { localization_only_ = on; }
  // Frames relocalized so far.
  [[nodiscard]] int relocalizations() const { return relocalizations_; }
  // Frames tracking moved faster than `tracking.max_camera_speed` (camera_stride.h), tracked
  // again from where the stride began or not.
  [[nodiscard]] int implausible_motions() const { return implausible_motions_; }

  // World-to-camera pose of the next frame, taken at `timestamp`, by the constant-velocity model
  // (empty when not tracking). Map mutex not needed: it reads the tracker's own state only; call
  // between frames.
  [[nodiscard]] std::optional<Eigen::Isometry3d> predicted_pose(double timestamp) const;

  [[nodiscard]] TrackingState state() const { return state_; }
  [[nodiscard]] const std::vector<FrameRecord>& records() const { return records_; }
  [[nodiscard]] const TrackerParams& params() const { return params_; }

 private:
  // Each step returns whether the frame is still tracked.
  map::KeyFrame* initialize(data::Frame& frame);
  bool track_frame(data::Frame& frame, TrackOutcome& outcome);
  bool localize_in_loaded_map(data::Frame& frame, TrackOutcome& outcome);
  bool track_reference_keyframe(data::Frame& frame);
  // Descriptor matching against `kf`, then motion-only BA from `T_cw` (the reference keyframe's
  // fallback, and tracking again from an earlier pose).
  bool track_keyframe(data::Frame& frame, const map::KeyFrame& kf, const Eigen::Isometry3d& T_cw);
  bool relocalize(data::Frame& frame);  // relocalization.cc
  // Lost: relocalization, or the last reference keyframe from the last pose (camera_speed_check.cc).
  bool recover(data::Frame& frame, TrackOutcome& outcome);
  // Metres from the last tracked pose to the frame's, when a camera within its speed limit cannot
  // have gone so far in the time it was lost (nothing after a second lost, or without a limit).
  [[nodiscard]] std::optional<double> implausible_recovery(const data::Frame& frame) const;
  // The last frame tracked against a keyframe (null: none yet).
  [[nodiscard]] const FrameRecord* last_tracked_record() const;
  // Tells the crossing callback that `frame`, relocalized against `found`, crossed the map.
  void suggest_crossing(const data::Frame& frame, const map::KeyFrame& found) const;
  // Metres from the tracked frame `from` to `frame`, when more than the speed limit allows between
  // their stamps.
  [[nodiscard]] std::optional<double> beyond_speed_limit(const FrameRecord& from,
                                                         const data::Frame& frame) const;
  bool track_with_motion_model(data::Frame& frame);
  bool track_local_map(data::Frame& frame);
  int optimize_pose(data::Frame& frame);
  // Debug log: the frame's live pose and its step from the last frame (as its keyframe stands now).
  void log_live_pose(const data::Frame& frame) const;
  void update_last_frame();
  // Tracking links between the last frame's reference keyframe and this one's (map mutex held).
  void link_references(std::optional<std::uint64_t> previous, map::KeyFrame* current);
  void record(const data::Frame& frame);
  // Drops or replaces the pointers it keeps to the next frame that lead to removed keyframes or
  // map points, then tells the map's reclamation so (map mutex held).
  void let_go_of_removed_objects();
  [[nodiscard]] bool recently_recovered(const data::Frame& frame) const;
  // When the camera's stride up to this tracked frame is beyond its speed limit (camera_speed_check.cc),
  // tracks the frame again from where the stride began, and takes that when it makes the stride
  // one the camera can make.
  void check_camera_speed(data::Frame& frame);
  bool track_again_from(data::Frame& frame, const FrameRecord& from);
  void replace_followed_frames(const FrameRecord& from, const data::Frame& found);
  // A step from the last tracked frame beyond the speed limit, back within it of an earlier frame
  // and with more inliers: the frames between are placed again on the path from that one (true
  // when they were).
  bool replace_frames_before_a_return(const data::Frame& frame);
  [[nodiscard]] std::optional<FrameRecord> return_anchor(const data::Frame& frame,
                                                         const FrameRecord& last) const;
  // A relocalization soon after frames the speed check flagged and kept places them on the path
  // from where they began to follow to the relocalized pose, when the camera could make it.
  void replace_frames_followed_before_loss(const data::Frame& relocalized);
  // What a search of the local map leaves in the tracker (kept to undo a second search).
  struct SearchState {
    map::KeyFrame* reference;
    LocalMap::Contents local_map;
    int inliers;
  };
  [[nodiscard]] Eigen::Isometry3d motion_model_pose(double timestamp) const;

  map::Map& map_;
  mapping::LocalMapper& mapper_;
  TrackerParams params_;
  KeyFrameInserter keyframes_;
  match::OrbMatcher motion_matcher_;     // nn 0.9, rotation check
  match::OrbMatcher reference_matcher_;  // nn 0.7, rotation check

  TrackingState state_ = TrackingState::NotInitialized;
  map::ReclamationMembership reclamation_;
  std::optional<data::Frame> last_frame_;
  std::optional<std::uint64_t> last_frame_reference_;
  // The reference keyframe of the frame just before, if it was tracked (for the tracking links).
  std::optional<std::uint64_t> previous_reference_;
  Eigen::Isometry3d last_T_c_ref_ = Eigen::Isometry3d::Identity();
  MotionModel motion_;
  map::KeyFrame* reference_kf_ = nullptr;
  std::uint64_t recovered_frame_id_ = 0;
  bool recovered_ = false;
  int inliers_ = 0;
  LocalMap local_map_;
  std::vector<FrameRecord> records_;
  dynamic::MovingPointCheck* moving_point_check_ = nullptr;
  const place::Vocabulary* vocabulary_ = nullptr;
  map::KeyFrameDatabase* database_ = nullptr;
  int relocalizations_ = 0;
  int implausible_motions_ = 0;
  // Tags map points and keyframes met by one search of the map (a frame may be searched twice).
  std::uint64_t search_pass_ = 0;
  // This frame was tracked again from an earlier pose: no velocity or tracking link from the last.
  bool restarted_motion_ = false;
  // Where the stride of the first frame flagged and kept since the last stride within the limit
  // began, and the stamp of the last one so flagged (a relocalization soon after places them).
  std::optional<FrameRecord> followed_since_;
  double followed_until_ = 0.0;
  bool localization_only_ = false;
  CrossingCallback crossing_callback_;
};

}  // namespace lrd::tracking
