#include "lrd/mapping/local_mapper_params.h"

namespace lrd::mapping {

LocalMapperParams LocalMapperParams::from_config(config::NodeReader r) {
  LocalMapperParams p;
  p.triangulation_neighbours = r.get("triangulation_neighbours", p.triangulation_neighbours);
  r.check(p.triangulation_neighbours >= 0, "triangulation_neighbours", "must be >= 0");
  p.fuse_neighbours = r.get("fuse_neighbours", p.fuse_neighbours);
  r.check(p.fuse_neighbours >= 0, "fuse_neighbours", "must be >= 0");
  p.fuse_second_neighbours = r.get("fuse_second_neighbours", p.fuse_second_neighbours);
  r.check(p.fuse_second_neighbours >= 0, "fuse_second_neighbours", "must be >= 0");
  p.local_ba = r.get("local_ba", p.local_ba);
  p.ba.first_iterations = r.get("ba_first_iterations", p.ba.first_iterations);
  p.ba.second_iterations = r.get("ba_second_iterations", p.ba.second_iterations);
  r.check(p.ba.first_iterations >= 1 && p.ba.second_iterations >= 0, "ba_first_iterations",
          "iterations must be positive");
  p.ba.max_local_keyframes = r.get("ba_max_local_keyframes", p.ba.max_local_keyframes);
  r.check(p.ba.max_local_keyframes >= 0, "ba_max_local_keyframes",
          "must be >= 0 (0: every covisible keyframe)");
  p.ba.max_odometry_change_m = r.get("ba_max_odometry_change_m", p.ba.max_odometry_change_m);
  r.check(p.ba.max_odometry_change_m > 0.0, "ba_max_odometry_change_m", "must be > 0");
  p.ba.max_odometry_change_deg = r.get("ba_max_odometry_change_deg", p.ba.max_odometry_change_deg);
  r.check(p.ba.max_odometry_change_deg > 0.0, "ba_max_odometry_change_deg", "must be > 0");
  p.keyframe_culling = r.get("keyframe_culling", p.keyframe_culling);
  KeyFrameCullingParams& c = p.culling;
  c.redundant_ratio = r.get("redundant_ratio", c.redundant_ratio);
  r.check(c.redundant_ratio > 0.0 && c.redundant_ratio <= 1.0, "redundant_ratio", "must be in (0, 1]");
  c.redundant_observers = r.get("redundant_observers", c.redundant_observers);
  r.check(c.redundant_observers >= 1, "redundant_observers", "must be >= 1");
  c.place_redundant_ratio = r.get("place_redundant_ratio", c.place_redundant_ratio);
  r.check(c.place_redundant_ratio >= 0.0 && c.place_redundant_ratio <= 1.0, "place_redundant_ratio",
          "must be in [0, 1] (0: no place rule)");
  c.place_baseline_ratio = r.get("place_baseline_ratio", c.place_baseline_ratio);
  r.check(c.place_baseline_ratio > 0.0, "place_baseline_ratio", "must be > 0");
  c.place_angle_deg = r.get("place_angle_deg", c.place_angle_deg);
  r.check(c.place_angle_deg > 0.0 && c.place_angle_deg < 90.0, "place_angle_deg", "must be in (0, 90)");
  c.place_keyframes_apart = r.get("place_keyframes_apart", c.place_keyframes_apart);
  r.check(c.place_keyframes_apart >= 1, "place_keyframes_apart", "must be >= 1");
  p.max_queued = r.get("max_queued", p.max_queued);
  r.check(p.max_queued >= 1, "max_queued", "must be >= 1");
  r.finish();
  return p;
}

}  // namespace lrd::mapping
