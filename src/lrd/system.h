#pragma once
// lrd::System: the library's front door. Feed it RGB-D frames; it tracks the camera against a
// map it builds on the fly (tracking in the caller's thread, local mapping in its own), and
// saves the trajectory. Typical use:
//
//   lrd::config::Config cfg = lrd::config::load_config("config/default.yaml");
//   lrd::System slam(cfg);
//   for (...) { auto r = slam.track_rgbd(rgb, depth, t); if (r.state == lrd::TrackingState::Ok) ... }
//   slam.shutdown();
//   slam.save_trajectory_tum("CameraTrajectory.txt");
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "lrd/config/config.h"
#include "lrd/dense/dense_mapper.h"
#include "lrd/dynamic/dynamic_params.h"
#include "lrd/events/event_publisher.h"
#include "lrd/events/map_snapshot.h"
#include "lrd/io/trajectory.h"
#include "lrd/loop/loop_closer.h"
#include "lrd/map/map_memory.h"
#include "lrd/occupancy/occupancy_builder.h"
#include "lrd/segmentation/segmentation_params.h"
#include "lrd/system_params.h"
#include "lrd/tracking/tracking_state.h"

namespace lrd {

using tracking::TrackingState;

using events::FrameTiming;

// What the dynamic-scene stages did with one frame.
struct DynamicInfo {
  std::int64_t mask_frame = -1;  // frame index of the segmentation mask used (-1: none)
  int mask_age = -1;             // frames between that mask and this frame (-1: none)
  int geometric_keypoints = 0;   // keypoints the geometry check removed
  int geometric_seeds = 0;       // projected points it found moving
  int keypoints = 0;             // keypoints left for tracking
  cv::Mat mask;                  // the frame's dynamic pixels (CV_8UC1 nonzero; empty: none)
};

struct TrackResult {
  TrackingState state = TrackingState::NotInitialized;
  std::optional<Eigen::Isometry3d> T_wc;  // camera-to-world, when tracking is OK
  FrameTiming timing;
  int inliers = 0;  // map points matched and kept by the pose optimization
  DynamicInfo dynamic;
  // The local map it was tracked against (keyframes, map points); 0 when not tracked.
  std::size_t local_keyframes = 0, local_points = 0;
};

struct MapStats {
  std::size_t keyframes = 0;
  std::size_t map_points = 0;
  std::size_t culled_keyframes = 0;
  std::size_t bundle_adjustments = 0;
  std::size_t implausible_local_bundle_adjustments = 0;  // solved but refused (optim/local_bundle_adjuster.h)
  std::size_t loops = 0;                                 // loops closed
  int relocalizations = 0;  // times tracking was lost (or not yet localized in a loaded map) and relocalized
  // Frames tracking moved faster than tracking.max_camera_speed (it followed a person), tracked
  // again from where that began or not (tracking/camera_stride.h).
  int implausible_camera_motions = 0;
  std::size_t loaded_keyframes = 0;  // keyframes and map points load_map() brought in
  std::size_t loaded_map_points = 0;
  int global_bundle_adjustments = 0;
  int implausible_global_bundle_adjustments = 0;  // solved but not merged (optim/global_bundle_adjuster.h)
  int rejected_loops = 0;  // detected but contradicted by the map (loop/loop_agreement.h)
};

// A map save in two steps (System::capture_map): what can change in the map was copied under its
// mutex; serialize() builds the file's bytes, in any thread, from the copy and the keyframes'
// features, which never change. While it lives, keyframes culled since the copy are not freed:
// let it go before the System is reset or destroyed.
class PendingMapSave {
 public:
  struct State;
  PendingMapSave(std::unique_ptr<State> state, double lock_seconds);
  ~PendingMapSave();
  PendingMapSave(PendingMapSave&&) noexcept = default;
  PendingMapSave& operator=(PendingMapSave&&) = delete;

  [[nodiscard]] std::string serialize() const;                         // the .lrdmap file's bytes
  [[nodiscard]] double lock_seconds() const { return lock_seconds_; }  // the map mutex held

 private:
  std::unique_ptr<State> state_;
  double lock_seconds_ = 0.0;
};

class System {
 public:
  // Reads every module's parameters from `config` (SystemParams::from_config) with `options`'
  // overrides, loads the vocabulary and starts the threads.
  explicit System(const config::Config& config, SystemOptions options = {});
  // With parameters already read (the overrides in `options` are not applied again).
  System(const config::Config& config, SystemParams params, SystemOptions options);
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  // rgb: CV_8UC3 in the camera's colour order (Camera.RGB) or CV_8UC1 grey; depth: CV_16UC1 raw
  // (divided by depth_map_factor) or CV_32FC1 metres, same size, registered to the colour image;
  // mask (optional): CV_8UC1, nonzero = dynamic, no features there. Throws lrd::Error for images
  // of the wrong type or size; timestamps must increase.
  TrackResult track_rgbd(const cv::Mat& rgb, const cv::Mat& depth, double timestamp,
                         const cv::Mat& mask = {});

  // Finishes local mapping, loop closing and the dense map on the queued keyframes, delivers the
  // queued events and joins every thread. Idempotent; called by the destructor. Throws the first
  // error any worker thread met, as an lrd::Error naming the thread (so does track_rgbd).
  void shutdown();
  // Starts a new map in the same process: the threads of the current one finish and stop, a new
  // map begins with the next frame (frame ids continue; the trajectory is the new map's). A
  // loaded map (load_map) goes too.
  void reset();

  // --- publishers (events/events.h). Register before the first frame; events are delivered on
  // the publisher's own thread, in order, and never make tracking wait.
  void subscribe(std::shared_ptr<events::Subscriber> subscriber);
  [[nodiscard]] events::PublisherStats publisher_stats() const;
  // Thread-safe copies of the map now: keyframe poses and map points with their keyframes.
  [[nodiscard]] events::MapSnapshot map_snapshot() const;

  // Camera-to-world poses of every tracked frame (lost frames left out), computed from their
  // reference keyframes' current poses.
  [[nodiscard]] io::Trajectory trajectory() const;
  [[nodiscard]] io::Trajectory keyframe_trajectory() const;
  void save_trajectory_tum(const std::filesystem::path& file) const;
  void save_keyframe_trajectory_tum(const std::filesystem::path& file) const;

  // --- map files (map/map_file.h, docs/map-files.md)
  // Writes the map as it is now (after shutdown(): the final one) to `file` (.lrdmap), whole or
  // not at all; any thread, while frames are tracked (tracking waits only while the map's
  // changing parts are copied: capture_map). Throws lrd::Error naming the file.
  void save_map(const std::filesystem::path& file) const;
  // save_map's first step, for a saver that builds and writes the bytes at its own pace (on a
  // thread of low priority): any thread, while frames are tracked. Throws lrd::Error without a
  // vocabulary.
  [[nodiscard]] PendingMapSave capture_map() const;
  // Starts from a saved map instead of an empty one: the first frames relocalize against it and
  // are reported not-localized until one is placed; the trajectory is in the map's frame. Call
  // before the first frame. Throws lrd::Error naming the file for a bad file, or one made with
  // another vocabulary or camera; the system is then unchanged.
  void load_map(const std::filesystem::path& file);
  [[nodiscard]] bool localization_only() const;

  [[nodiscard]] MapStats map_stats() const;
  // Memory the map holds, and what reclamation freed (walks every object: not for every frame).
  [[nodiscard]] map::MapMemory map_memory() const;
  // Each loop closed so far (frame, keyframes, inliers, correction).
  [[nodiscard]] std::vector<loop::LoopEvent> loops() const;
  // Each global bundle adjustment run after a loop so far (size and latency).
  [[nodiscard]] std::vector<loop::GlobalBaRun> global_ba_runs() const;
  [[nodiscard]] bool loop_closing_enabled() const;
  // Place recognition (relocalization; loop closing): the vocabulary file in use, or empty.
  [[nodiscard]] std::filesystem::path vocabulary_file() const;
  [[nodiscard]] TrackingState state() const;
  [[nodiscard]] const config::Config& config() const;
  [[nodiscard]] dynamic::DynamicMode mode() const;
  // "masks (seq/mask), async" or "none".
  [[nodiscard]] std::string segmentation_description() const;

  // --- dense map (when dense.enabled or SystemOptions::dense)
  [[nodiscard]] bool dense_enabled() const;
  // The dense map at the keyframes' current poses (empty without the dense stage). Call after
  // shutdown() for the complete map.
  [[nodiscard]] dense::PointCloud dense_map() const;
  [[nodiscard]] dense::RepairTotals repair_totals() const;
  // What the dense stage keeps per keyframe (dense.max_memory_mb caps it).
  [[nodiscard]] dense::DenseStorage dense_storage() const;
  // Called in the dense thread after each keyframe's background repair; set before tracking.
  void set_repair_callback(dense::DenseMapper::RepairCallback callback);
  // --- occupancy (docs/occupancy.md): with the dense stage unless occupancy.enabled is false
  [[nodiscard]] bool occupancy_enabled() const;
  [[nodiscard]] const occupancy::OccupancyParams& occupancy_params() const;
  // The OctoMap, floor and 2-D grid of the dense stage's keyframes at their current poses, built
  // in the caller's thread (seconds on a long run: not in a tracking callback). Empty without the
  // dense stage.
  [[nodiscard]] occupancy::Occupancy occupancy() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lrd
