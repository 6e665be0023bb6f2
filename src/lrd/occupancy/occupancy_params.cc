#include "lrd/occupancy/occupancy_params.h"

#include <vector>

namespace lrd::occupancy {

OccupancyParams OccupancyParams::from_config(config::NodeReader r) {
  OccupancyParams p;
  p.enabled = r.get("enabled", p.enabled);
  p.resolution = r.get("resolution", p.resolution);
  r.check(p.resolution > 0 && p.resolution <= 1.0, "resolution", "must be in (0, 1] m");
  p.max_range = r.get("max_range", p.max_range);
  r.check(p.max_range > p.resolution, "max_range", "must be larger than the resolution");
  p.prob_hit = r.get("prob_hit", p.prob_hit);
  r.check(p.prob_hit > 0.5 && p.prob_hit < 1.0, "prob_hit", "must be in (0.5, 1)");
  p.prob_miss = r.get("prob_miss", p.prob_miss);
  r.check(p.prob_miss > 0.0 && p.prob_miss < 0.5, "prob_miss", "must be in (0, 0.5)");
  p.clamp_min = r.get("clamp_min", p.clamp_min);
  p.clamp_max = r.get("clamp_max", p.clamp_max);
  r.check(p.clamp_min > 0.0 && p.clamp_min < 0.5, "clamp_min", "must be in (0, 0.5)");
  r.check(p.clamp_max > 0.5 && p.clamp_max < 1.0, "clamp_max", "must be in (0.5, 1)");
  p.depth_noise = r.get("depth_noise", p.depth_noise);
  r.check(p.depth_noise >= 0.0, "depth_noise", "must be >= 0");
  p.min_hit_keyframes = r.get("min_hit_keyframes", p.min_hit_keyframes);
  r.check(p.min_hit_keyframes >= 1, "min_hit_keyframes", "must be >= 1");
  p.min_hit_interval = r.get("min_hit_interval", p.min_hit_interval);
  r.check(p.min_hit_interval >= 0.0, "min_hit_interval", "must be >= 0 s");
  p.min_height = r.get("min_height", p.min_height);
  p.max_height = r.get("max_height", p.max_height);
  r.check(p.max_height > p.min_height, "max_height", "must be above min_height (the heights are inverted)");
  p.filter_speckles = r.get("filter_speckles", p.filter_speckles);
  const std::vector<double> up = r.get("up", std::vector<double>{p.up.x(), p.up.y(), p.up.z()});
  r.check(up.size() == 3, "up", "must be three numbers [x, y, z]");
  p.up = Eigen::Vector3d(up[0], up[1], up[2]);
  r.check(p.up.norm() > 1e-6, "up", "must not be zero");
  p.up.normalize();
  if (r.has("floor_height")) {
    const std::string text = r.get("floor_height", std::string("auto"));
    if (text != "auto") {
      p.floor_height = r.get("floor_height", 0.0);  // converts or names the key and line
    }
  }
  p.occupied_thresh = r.get("occupied_thresh", p.occupied_thresh);
  p.free_thresh = r.get("free_thresh", p.free_thresh);
  r.check(p.free_thresh > 0.0 && p.free_thresh < p.occupied_thresh && p.occupied_thresh < 1.0, "free_thresh",
          "needs 0 < free_thresh < occupied_thresh < 1");
  r.finish();
  return p;
}

}  // namespace lrd::occupancy
