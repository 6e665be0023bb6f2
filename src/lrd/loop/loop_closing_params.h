#pragma once
// The `loop_closing` section of the config, typed.
#include <filesystem>

#include "lrd/config/node_reader.h"
#include "lrd/loop/loop_detector.h"

namespace lrd::loop {

struct LoopClosingParams {
  bool enabled = true;
  std::filesystem::path vocabulary;  // empty: the shipped vocab/orb_vocab.lrdv
  LoopDetectorParams detector;
  int essential_min_weight = 100;  // covisibility edges kept in the essential graph
  int pose_graph_iterations = 20;
  bool global_ba = true;
  int global_ba_iterations = 10;
  // A global BA result that moves a keyframe further against its spanning-tree parent is
  // implausible and not merged (optim/global_bundle_adjuster.h).
  double global_ba_max_edge_change_m = 0.1;
  double global_ba_max_edge_change_deg = 5.0;
  // A loop whose pose-graph correction would change a keyframe's pose against its spanning-tree
  // parent by more than this, or leave the loop open by more, is refused (loop_solution.h).
  double pose_graph_max_edge_change_m = 0.25;
  double pose_graph_max_edge_change_deg = 10.0;
  // Reads the `loop_closing` section of the config (and finishes it); relative paths are
  // relative to `base_dir` (the config file's folder).
  static LoopClosingParams from_config(config::NodeReader reader, const std::filesystem::path& base_dir);
};

}  // namespace lrd::loop
