#pragma once
// The `dynamic` section of the config: which dynamic-scene mode runs (paper §2.5, Algorithm 1)
// and the multi-view geometry check's settings (§2.7, Fig. 5).
#include <string>

#include "lrd/config/node_reader.h"

namespace lrd::dynamic {

enum class DynamicMode {
  Static,     // ORB-SLAM2: every feature is used
  Semantic,   // LRD-SLAM (P): features under the segmentation mask are dropped
  Geometric,  // multi-view geometry check only
  Full,       // LRD-SLAM (C): union of the semantic mask and the geometric flags
};

[[nodiscard]] std::string to_string(DynamicMode m);
// "static" | "semantic" | "geometric" | "full"; throws lrd::Error naming the choices.
[[nodiscard]] DynamicMode parse_mode(const std::string& name);
[[nodiscard]] inline bool uses_segmentation(DynamicMode m) {
  return m == DynamicMode::Semantic || m == DynamicMode::Full;
}
[[nodiscard]] inline bool uses_geometry(DynamicMode m) {
  return m == DynamicMode::Geometric || m == DynamicMode::Full;
}

struct GeometryCheckParams {
  int keyframes = 5;                     // keyframes overlapping most with the frame are compared
  double max_parallax_deg = 30.0;        // above: the point is not judged (occlusion risk, DynaSLAM)
  double depth_threshold = 0.10;         // tau_z: z_proj - z' above this (metres) => dynamic
  double depth_threshold_slope = 0.02;   // ... plus this x z_proj (depth noise grows with distance)
  double max_depth = 6.0;                // points farther than this are not judged (noisy depth)
  int neighbourhood = 2;                 // half-size of the depth patch around the projection
  double neighbourhood_agreement = 0.7;  // share of the patch that must agree that it is closer
  int min_seeds = 3;                     // fewer flagged points around a seed are noise, not an object
  double seed_support = 0.5;             // share of judged points around a seed that must agree
  // A candidate seed with a keyframe point projected within this many pixels at the depth now
  // measured lies on static foreground that hides the point (occlusion, not motion); 0: off.
  int known_surface_px = 8;
  // Region growing (on a half-resolution depth image) from each flagged point.
  double grow_step = 0.03;          // neighbour-to-neighbour depth step (m), + 1 % of depth
  double grow_band = 0.35;          // at most this far in depth from the seed (m)
  double grow_extent = 0.8;         // at most this far sideways from the seed (m)
  int region_dilation_px = 5;       // the grown regions are dilated by this radius
  double min_keyframe_age_s = 0.2;  // younger keyframes show too little object motion
};

struct DynamicParams {
  // The default needs no model (the shipped FNet-lite knows only synthetic renders).
  DynamicMode mode = DynamicMode::Geometric;
  GeometryCheckParams geometry;

  // Reads the `dynamic` section (and finishes it).
  static DynamicParams from_config(config::NodeReader reader);
};

}  // namespace lrd::dynamic
