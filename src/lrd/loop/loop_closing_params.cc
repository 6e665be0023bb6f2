#include "lrd/loop/loop_closing_params.h"

namespace lrd::loop {

LoopClosingParams LoopClosingParams::from_config(config::NodeReader r,
                                                 const std::filesystem::path& base_dir) {
  LoopClosingParams p;
  p.enabled = r.get("enabled", p.enabled);
  p.vocabulary = r.get("vocabulary", p.vocabulary);
  if (!p.vocabulary.empty() && p.vocabulary.is_relative() && !base_dir.empty())
    p.vocabulary = base_dir / p.vocabulary;
  p.detector.consistency = r.get("consistency", p.detector.consistency);
  r.check(p.detector.consistency >= 1, "consistency", "must be >= 1");
  p.detector.min_keyframes_between = r.get("min_keyframes_between", p.detector.min_keyframes_between);
  p.detector.min_bow_matches = r.get("min_bow_matches", p.detector.min_bow_matches);
  p.detector.min_ransac_inliers = r.get("min_ransac_inliers", p.detector.min_ransac_inliers);
  r.check(p.detector.min_ransac_inliers >= 3, "min_ransac_inliers", "must be >= 3");
  p.detector.min_matches = r.get("min_matches", p.detector.min_matches);
  p.detector.ransac_iterations = r.get("ransac_iterations", p.detector.ransac_iterations);
  r.check(p.detector.ransac_iterations >= 1, "ransac_iterations", "must be >= 1");
  p.essential_min_weight = r.get("essential_min_weight", p.essential_min_weight);
  p.pose_graph_iterations = r.get("pose_graph_iterations", p.pose_graph_iterations);
  r.check(p.pose_graph_iterations >= 1, "pose_graph_iterations", "must be >= 1");
  p.global_ba = r.get("global_ba", p.global_ba);
  p.global_ba_iterations = r.get("global_ba_iterations", p.global_ba_iterations);
  r.check(p.global_ba_iterations >= 1, "global_ba_iterations", "must be >= 1");
  p.global_ba_max_edge_change_m = r.get("global_ba_max_edge_change_m", p.global_ba_max_edge_change_m);
  r.check(p.global_ba_max_edge_change_m > 0.0, "global_ba_max_edge_change_m", "must be > 0");
  p.global_ba_max_edge_change_deg = r.get("global_ba_max_edge_change_deg", p.global_ba_max_edge_change_deg);
  r.check(p.global_ba_max_edge_change_deg > 0.0, "global_ba_max_edge_change_deg", "must be > 0");
  p.pose_graph_max_edge_change_m = r.get("pose_graph_max_edge_change_m", p.pose_graph_max_edge_change_m);
  r.check(p.pose_graph_max_edge_change_m > 0.0, "pose_graph_max_edge_change_m", "must be > 0");
  p.pose_graph_max_edge_change_deg =
      r.get("pose_graph_max_edge_change_deg", p.pose_graph_max_edge_change_deg);
  r.check(p.pose_graph_max_edge_change_deg > 0.0, "pose_graph_max_edge_change_deg", "must be > 0");
  r.finish();
  return p;
}

}  // namespace lrd::loop
