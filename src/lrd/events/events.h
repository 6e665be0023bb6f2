#pragma once
// What lrd::System tells the world, as plain values (no pointers into the live map): viewers,
// the CLI runner, the ROS node and the report subscribe to these instead of reaching into the
// system. Delivered in order, on the publisher's own thread (events/event_publisher.h).
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "lrd/dense/background_repairer.h"
#include "lrd/dense/rgbd_view.h"
#include "lrd/tracking/tracking_state.h"

namespace lrd::events {

// Where the time of one frame went, in seconds.
struct FrameTiming {
  double extraction = 0.0;    // colour conversion, ORB extraction, undistortion, grid
  double segmentation = 0.0;  // the network on the mask used (its own thread: not in total())
  double mask_wait = 0.0;     // tracking waiting for the mask, and carrying an older one over
  double geometry = 0.0;      // multi-view geometry check and region growing
  double tracking = 0.0;      // pose estimation, local map, keyframe decision
  double waiting = 0.0;       // waiting for local mapping to release the map
  double mapping = 0.0;       // lock-step local mapping (deterministic mode only)
  double yardstick = 0.0;     // OpenCV ORB on this frame (SystemOptions::yardstick; not in total())
  [[nodiscard]] double total() const {
    return extraction + mask_wait + geometry + tracking + waiting + mapping;
  }
};

// One frame, tracked or not.
// Every event names the map it belongs to: System::reset() starts map 1, 2, ... (keyframe ids
// start again at 0 in each), so a subscriber can tell an old map's late events from the new one's.

struct FrameTracked {
  std::uint32_t map = 0;
  std::uint64_t frame_id = 0;  // 0, 1, 2, ... in the order given to track_rgbd
  double timestamp = 0.0;
  tracking::TrackingState state = tracking::TrackingState::NotInitialized;
  std::optional<Eigen::Isometry3d> T_wc;  // camera-to-world when tracked
  FrameTiming timing;
  int inliers = 0;
  std::int64_t mask_frame = -1;  // the frame whose segmentation mask was used (-1: none)
  int mask_age = -1;
  int geometric_keypoints = 0;  // keypoints the geometry check removed
  bool relocalized = false;
  std::optional<std::uint64_t> new_keyframe;   // id of the keyframe this frame became
  cv::Mat grey;                                // the frame (CV_8UC1), its own buffer
  cv::Mat mask;                                // dynamic pixels (CV_8UC1 nonzero; empty: none)
  std::vector<cv::Point2f> kept_keypoints;     // used for tracking (as detected)
  std::vector<cv::Point2f> removed_keypoints;  // removed by the geometry check
};

struct KeyframeInserted {
  std::uint32_t map = 0;
  std::uint64_t keyframe_id = 0;
  std::uint64_t frame_id = 0;
  double timestamp = 0.0;
  Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
  std::size_t map_points = 0;  // points the keyframe observes
};

struct KeyframePose {
  std::uint64_t keyframe_id = 0;
  double timestamp = 0.0;
  Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
};

// A loop was closed: the pose graph has moved the keyframes (poses after the correction).
struct LoopClosed {
  std::uint32_t map = 0;
  std::uint64_t frame_id = 0;
  double timestamp = 0.0;
  std::uint64_t keyframe_id = 0;
  std::uint64_t loop_keyframe_id = 0;
  int inliers = 0;
  double correction_m = 0.0;
  std::vector<KeyframePose> corrected;  // every keyframe of the map
};

// Local mapping finished a keyframe: what it changed in the map.
struct MapChanged {
  std::uint32_t map = 0;
  std::uint64_t keyframe_id = 0;
  std::size_t keyframes = 0;            // in the map now
  std::size_t map_points = 0;           // in the map now
  std::size_t culled_keyframes = 0;     // so far
  std::size_t triangulated_points = 0;  // so far
};

// The dense stage integrated a keyframe (its images are shared with the dense stage: read only).
struct DenseMapUpdated {
  std::uint32_t map = 0;
  double timestamp = 0.0;  // the keyframe's
  std::size_t keyframes = 0;
  std::size_t dynamic_pixels = 0;             // in this keyframe
  std::size_t filled_pixels = 0;              // of those, repaired
  dense::RgbdView keyframe;                   // colour, depth and dynamic mask as tracking gave them
  std::optional<dense::RepairResult> repair;  // the background repair, when it had dynamic pixels
};

}  // namespace lrd::events
