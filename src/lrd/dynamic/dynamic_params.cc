#include "lrd/dynamic/dynamic_params.h"

#include "lrd/util/error.h"

namespace lrd::dynamic {

std::string to_string(DynamicMode m) {
  switch (m) {
    case DynamicMode::Static:
      return "static";
    case DynamicMode::Semantic:
      return "semantic";
    case DynamicMode::Geometric:
      return "geometric";
    case DynamicMode::Full:
      return "full";
  }
  return "?";
}

DynamicMode parse_mode(const std::string& name) {
  for (DynamicMode m :
       {DynamicMode::Static, DynamicMode::Semantic, DynamicMode::Geometric, DynamicMode::Full})
    if (to_string(m) == name) return m;
  throw Error("unknown mode '" + name + "' (choose static, semantic, geometric or full)");
}

DynamicParams DynamicParams::from_config(config::NodeReader r) {
  DynamicParams p;
  const auto mode = r.get<std::string>("mode", to_string(p.mode));
  try {
    p.mode = parse_mode(mode);
  } catch (const Error& e) {
    r.check(false, "mode", e.what());
  }
  config::NodeReader g = r.section("geometry");
  GeometryCheckParams& q = p.geometry;
  q.keyframes = g.get("keyframes", q.keyframes);
  g.check(q.keyframes >= 1 && q.keyframes <= 50, "keyframes", "must be in [1, 50]");
  q.max_parallax_deg = g.get("max_parallax_deg", q.max_parallax_deg);
  g.check(q.max_parallax_deg > 0 && q.max_parallax_deg <= 180, "max_parallax_deg", "must be in (0, 180]");
  q.depth_threshold = g.get("depth_threshold", q.depth_threshold);
  g.check(q.depth_threshold > 0 && q.depth_threshold <= 10, "depth_threshold", "must be in (0, 10] m");
  q.depth_threshold_slope = g.get("depth_threshold_slope", q.depth_threshold_slope);
  g.check(q.depth_threshold_slope >= 0 && q.depth_threshold_slope <= 10, "depth_threshold_slope",
          "must be in [0, 10]");
  q.max_depth = g.get("max_depth", q.max_depth);
  g.check(q.max_depth > 0 && q.max_depth <= 100, "max_depth", "must be in (0, 100] m");
  q.neighbourhood = g.get("neighbourhood", q.neighbourhood);
  g.check(q.neighbourhood >= 0 && q.neighbourhood <= 10, "neighbourhood", "must be in [0, 10]");
  q.neighbourhood_agreement = g.get("neighbourhood_agreement", q.neighbourhood_agreement);
  g.check(q.neighbourhood_agreement >= 0 && q.neighbourhood_agreement <= 1, "neighbourhood_agreement",
          "must be in [0, 1]");
  q.min_seeds = g.get("min_seeds", q.min_seeds);
  q.seed_support = g.get("seed_support", q.seed_support);
  g.check(q.seed_support >= 0 && q.seed_support <= 1, "seed_support", "must be in [0, 1]");
  q.known_surface_px = g.get("known_surface_px", q.known_surface_px);
  g.check(q.known_surface_px >= 0 && q.known_surface_px <= 64, "known_surface_px",
          "must be in [0, 64] (0: off)");
  q.grow_step = g.get("grow_step", q.grow_step);
  q.grow_band = g.get("grow_band", q.grow_band);
  q.grow_extent = g.get("grow_extent", q.grow_extent);
  g.check(q.min_seeds >= 1, "min_seeds", "must be >= 1");
  g.check(q.grow_step > 0 && q.grow_step <= 100, "grow_step", "must be in (0, 100] m");
  g.check(q.grow_band > 0 && q.grow_band <= 100, "grow_band", "must be in (0, 100] m");
  g.check(q.grow_extent > 0 && q.grow_extent <= 100, "grow_extent", "must be in (0, 100] m");
  q.region_dilation_px = g.get("region_dilation_px", q.region_dilation_px);
  g.check(q.region_dilation_px >= 0 && q.region_dilation_px <= 50, "region_dilation_px",
          "must be in [0, 50]");
  q.min_keyframe_age_s = g.get("min_keyframe_age_s", q.min_keyframe_age_s);
  g.check(q.min_keyframe_age_s >= 0 && q.min_keyframe_age_s <= 3600, "min_keyframe_age_s",
          "must be in [0, 3600] s");
  g.finish();
  r.finish();
  return p;
}

}  // namespace lrd::dynamic
