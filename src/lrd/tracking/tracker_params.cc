#include "lrd/tracking/tracker_params.h"

namespace lrd::tracking {

TrackerParams TrackerParams::from_config(config::NodeReader r) {
  TrackerParams p;
  p.init_min_features = r.get("init_min_features", p.init_min_features);
  r.check(p.init_min_features >= 10, "init_min_features", "must be >= 10");
  p.motion_model_radius = r.get("motion_model_radius", p.motion_model_radius);
  r.check(p.motion_model_radius > 0 && p.motion_model_radius <= 1000, "motion_model_radius",
          "must be in (0, 1000]");
  p.min_motion_matches = r.get("min_motion_matches", p.min_motion_matches);
  r.check(p.min_motion_matches >= 0, "min_motion_matches", "must be >= 0");
  p.min_reference_matches = r.get("min_reference_matches", p.min_reference_matches);
  r.check(p.min_reference_matches >= 0, "min_reference_matches", "must be >= 0");
  p.min_pose_inliers = r.get("min_pose_inliers", p.min_pose_inliers);
  r.check(p.min_pose_inliers >= 0, "min_pose_inliers", "must be >= 0");
  p.min_local_map_inliers = r.get("min_local_map_inliers", p.min_local_map_inliers);
  r.check(p.min_local_map_inliers >= 0, "min_local_map_inliers", "must be >= 0");
  p.max_local_keyframes = r.get("max_local_keyframes", p.max_local_keyframes);
  r.check(p.max_local_keyframes >= 1, "max_local_keyframes", "must be >= 1");
  p.local_map_radius = r.get("local_map_radius", p.local_map_radius);
  r.check(p.local_map_radius > 0 && p.local_map_radius <= 1000, "local_map_radius", "must be in (0, 1000]");
  p.max_frames_between_keyframes = r.get("max_frames_between_keyframes", p.max_frames_between_keyframes);
  r.check(p.max_frames_between_keyframes >= 0, "max_frames_between_keyframes",
          "must be >= 0 (0: the camera's fps)");
  p.min_frames_between_keyframes = r.get("min_frames_between_keyframes", p.min_frames_between_keyframes);
  r.check(p.min_frames_between_keyframes >= 0, "min_frames_between_keyframes", "must be >= 0");
  p.reference_ratio = r.get("reference_ratio", p.reference_ratio);
  r.check(p.reference_ratio > 0 && p.reference_ratio <= 1, "reference_ratio", "must be in (0, 1]");
  p.keyframe_close_points = r.get("keyframe_close_points", p.keyframe_close_points);
  r.check(p.keyframe_close_points >= 0, "keyframe_close_points", "must be >= 0");
  p.keyframe_close_tracked = r.get("keyframe_close_tracked", p.keyframe_close_tracked);
  r.check(p.keyframe_close_tracked >= 0, "keyframe_close_tracked", "must be >= 0");
  p.keyframe_close_untracked = r.get("keyframe_close_untracked", p.keyframe_close_untracked);
  r.check(p.keyframe_close_untracked >= 0, "keyframe_close_untracked", "must be >= 0");
  p.keyframe_coverage = r.get("keyframe_coverage", p.keyframe_coverage);
  r.check(p.keyframe_coverage >= 0 && p.keyframe_coverage <= 1, "keyframe_coverage", "must be in [0, 1]");
  p.discount_hidden_points = r.get("discount_hidden_points", p.discount_hidden_points);
  p.min_relocalization_inliers = r.get("min_relocalization_inliers", p.min_relocalization_inliers);
  r.check(p.min_relocalization_inliers >= 6, "min_relocalization_inliers", "must be >= 6");
  p.max_camera_speed = r.get("max_camera_speed", p.max_camera_speed);
  r.check(p.max_camera_speed >= 0 && p.max_camera_speed <= 1000, "max_camera_speed",
          "must be in [0, 1000] (0: no limit)");
  r.finish();
  return p;
}

}  // namespace lrd::tracking
