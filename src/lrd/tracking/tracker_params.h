#pragma once
// The `tracking` section of the config, typed.
#include "lrd/config/node_reader.h"
#include "lrd/optim/pose_optimizer.h"

namespace lrd::tracking {

struct TrackerParams {
  int init_min_features = 500;          // keypoints with depth needed to start the map
  float motion_model_radius = 15.0f;    // search radius (px at level 0), ORB-SLAM2's RGB-D value
  int min_motion_matches = 20;          // below: widen the search once, then fall back
  int min_reference_matches = 15;       // reference-keyframe matching
  int min_pose_inliers = 10;            // after motion-only optimization
  int min_local_map_inliers = 30;       // tracking is OK above this
  int min_inliers_after_recovery = 50;  // ... for a second after recovering from loss
  int max_local_keyframes = 30;         // the local map: keyframes sharing the most points, then neighbours
  float local_map_radius = 1.0f;
  int max_frames_between_keyframes = 0;  // 0: the camera's fps
  int min_frames_between_keyframes = 0;
  double reference_ratio = 0.75;    // keyframe when tracked points fall below this share of the reference's
  int keyframe_close_points = 100;  // new keyframes create points from at least this many close depths
  // ORB-SLAM2's close-points rule: a keyframe when fewer close points than keyframe_close_tracked
  // are tracked and more than keyframe_close_untracked are not (the view has moved on to nearby
  // structure the map lacks). ORB-SLAM2 asks for 100: under noisy depth the tracked ones hover
  // near 100, the rule holds on most frames and local mapping fills a core (docs/slam-core.md).
  int keyframe_close_tracked = 50;
  int keyframe_close_untracked = 70;
  // Keyframe when the tracked close points span less than this share of the extent of all close
  // keypoints, across or down the image: a map seen in one strip of the view leaves rotation and
  // sideways translation nearly interchangeable (0: off, as ORB-SLAM2; docs/slam-core.md).
  double keyframe_coverage = 0.7;
  // The reference keyframe's points that project under this frame's dynamic mask are not counted
  // as lost: a person in front of the map hides it, the view has not moved on (docs/slam-core.md,
  // "Keyframes with people in view"). false: every point counts, as ORB-SLAM2.
  bool discount_hidden_points = true;
  int min_relocalization_inliers = 20;  // after motion-only BA on the PnP inliers
  // Tracking that moves the camera faster than this (m/s, over the last 0.2 s) has followed
  // something that moves, a person walking past, not the camera: the frame is tracked again from
  // where that stride began, and kept so when that is within the limit (camera_stride.h).
  // A hand-held camera or an indoor robot; raise it for faster platforms. 0: no limit.
  double max_camera_speed = 1.5;
  optim::PoseOptimizerParams pose;

  // Reads the `tracking` section of the config (and finishes it).
  static TrackerParams from_config(config::NodeReader reader);
};

}  // namespace lrd::tracking
