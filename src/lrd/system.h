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
#include <filesystem>
#include <memory>
#include <optional>
#include <opencv2/core.hpp>

#include "lrd/config/config.h"
#include "lrd/io/trajectory.h"
#include "lrd/tracking/tracking_state.h"

namespace lrd {

using tracking::TrackingState;

struct SystemOptions {
  // Local mapping in lock-step after each keyframe, in the tracking thread: two runs over the same
  // input give bit-identical trajectories (slower: tracking waits for mapping).
  bool deterministic = false;
};

// Where the time of one frame went, in seconds.
struct FrameTiming {
  double extraction = 0.0;  // colour conversion, ORB extraction, undistortion, grid
  double tracking = 0.0;    // pose estimation, local map, keyframe decision
  double waiting = 0.0;     // waiting for local mapping to release the map
  double mapping = 0.0;     // lock-step local mapping (deterministic mode only)
  [[nodiscard]] double total() const { return extraction + tracking + waiting + mapping; }
};

struct TrackResult {
  TrackingState state = TrackingState::NotInitialized;
  std::optional<Eigen::Isometry3d> T_wc;  // camera-to-world, when tracking is OK
  FrameTiming timing;
  int inliers = 0;  // map points matched and kept by the pose optimization
};

struct MapStats {
  std::size_t keyframes = 0;
  std::size_t map_points = 0;
  std::size_t culled_keyframes = 0;
  std::size_t bundle_adjustments = 0;
};

class System {
 public:
  explicit System(const config::Config& config, SystemOptions options = {});
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  // rgb: CV_8UC3 in the camera's colour order (Camera.RGB) or CV_8UC1 grey; depth: CV_16UC1 raw
  // (divided by depth_map_factor) or CV_32FC1 metres, same size, registered to the colour image;
  // mask (optional): CV_8UC1, nonzero = dynamic, no features there. Throws lrd::Error for images
  // of the wrong type or size; timestamps must increase.
  TrackResult track_rgbd(const cv::Mat& rgb, const cv::Mat& depth, double timestamp, const cv::Mat& mask = {});

  // Finishes local mapping on the queued keyframes and stops its thread. Idempotent; called by
  // the destructor.
  void shutdown();

  // Camera-to-world poses of every tracked frame (lost frames left out), computed from their
  // reference keyframes' current poses.
  [[nodiscard]] io::Trajectory trajectory() const;
  [[nodiscard]] io::Trajectory keyframe_trajectory() const;
  void save_trajectory_tum(const std::filesystem::path& file) const;
  void save_keyframe_trajectory_tum(const std::filesystem::path& file) const;

  [[nodiscard]] MapStats map_stats() const;
  [[nodiscard]] TrackingState state() const;
  [[nodiscard]] const config::Config& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lrd
