#include "lrd/loop/loop_solution.h"

#include <spdlog/spdlog.h>

#include <cstdint>

#include "lrd/loop/essential_graph.h"
#include "lrd/loop/loop_closer.h"
#include "lrd/map/map.h"

namespace lrd::loop {

Eigen::Isometry3d pose_in(const KeyFramePoses& poses, map::KeyFrame* k) {
  const auto it = poses.find(k);
  return it != poses.end() ? it->second : k->T_cw();
}

LoopGap loop_gap(const optim::SolvedPoses& T_cw, const LoopDetection& loop) {
  const Eigen::Isometry3d measured = loop.loop->T_cw() * loop.T_cw_corrected.inverse();
  const Eigen::Isometry3d solved = T_cw.at(loop.loop->id()) * T_cw.at(loop.current->id()).inverse();
  return optim::motion_size(measured.inverse() * solved);
}

// The plausibility check of a loop's correction (the divergence hunt, bench/results/divergence.md):
// a dry run of step 3 on the graph as it is, with the loop's edge and the neighbourhood moved. A
// correction that changes one spanning-tree edge by decimetres has not spread a drift along the
// loop: it would tear the trajectory apart (the 0.5-0.8 m jumps of `static` mode on walking_rpy).
// Warns when it refuses; otherwise returns its solution, which the correction falls back on
// (step 3).
std::optional<optim::PoseGraphResult> plausible_correction(
    const map::Map& map, const LoopClosingParams& params, const LoopDetection& loop,
    const KeyFramePoses& uncorrected, const KeyFramePoses& corrected, double correction_m) {
  const std::vector<map::KeyFrame*> all = map.keyframes();
  const optim::PoseOf pre = [&](map::KeyFrame* k) { return pose_in(uncorrected, k); };
  // The fusion will link the neighbourhood across the loop: each of its keyframes to the loop
  // keyframe at its corrected pose stands in for those links.
  EssentialGraph graph;
  graph.add_edge(loop.current, loop.loop, loop.loop->T_cw() * loop.T_cw_corrected.inverse());
  for (const auto& [k, T_cw] : corrected)
    if (k != loop.loop) graph.add_edge(k, loop.loop, loop.loop->T_cw() * T_cw.inverse());
  graph.add_map_edges(all, pre, params.essential_min_weight);
  const optim::PoseGraphResult result = graph.solve(
      all, [&](map::KeyFrame* k) { return pose_in(corrected, k); }, loop.loop, params.pose_graph_iterations);
  const optim::OdometryChange change =
      optim::largest_odometry_change(all, pre, [&](map::KeyFrame* k) { return result.T_cw.at(k->id()); });
  const double max_m = params.pose_graph_max_edge_change_m, max_deg = params.pose_graph_max_edge_change_deg;
  // A solution that cannot close the loop: the map between the two keyframes holds together
  // against it (keyframes that drifted together, all covisible). Fusing the loop's points anyway
  // would leave those keyframes where they are and their points where the loop puts them, and
  // tracking would jump between the two (`static` walking_static: a 0.71 m correction closed to
  // 0.55 m, a 0.80 m jump).
  const LoopGap gap = loop_gap(result.T_cw, loop);
  if (change.within(max_m, max_deg) && gap.within(max_m, max_deg)) {
    spdlog::debug(
        "loop {}-{}: correction {:.3f} m, dry run moves keyframe {} by {:.3f} m / {:.2f} deg against "
        "keyframe {}, leaves the loop {:.3f} m / {:.2f} deg open",
        loop.current->id(), loop.loop->id(), correction_m, change.keyframe, change.metres, change.degrees,
        change.other, gap.metres, gap.degrees);
    return result;
  }
  if (!gap.within(max_m, max_deg)) {
    spdlog::warn(
        "loop {}-{} rejected: the pose graph closes its correction ({:.3f} m) only to {:.3f} m / {:.1f} deg "
        "(at most {} m / {} deg): the map between the two keyframes holds together against it",
        loop.current->id(), loop.loop->id(), correction_m, gap.metres, gap.degrees, max_m, max_deg);
    return std::nullopt;
  }
  spdlog::warn(
      "loop {}-{} rejected: its correction ({:.3f} m) would {}, its parent or tracked beside it (at most {} "
      "m / {} deg): the drift is not spread along the loop",
      loop.current->id(), loop.loop->id(), correction_m, change.beyond(max_m, max_deg), max_m, max_deg);
  return std::nullopt;
}

// The dry run judged an approximation of the real solve (the fusion's links stood in by edges to
// the loop keyframe). The fusion's own links can still tear the odometry (walking_halfsphere in
// `static` mode: keyframe 86 moved 0.54 m against its parent 85, 5 cm apart in truth), or hold the
// loop open: a neighbourhood keyframe now sharing points with a keyframe that drifted with it but
// was not moved (`static` walking_static: a 1.58 m correction left 1.35 m open). The fused points
// are where the loop puts them, so their keyframes must be too: the map then takes the dry run's
// solution, which kept every pair within the limits and closed the loop. Returns whether it did.
bool settle_on_plausible_solution(const std::vector<map::KeyFrame*>& all, const optim::PoseOf& pre,
                                  const LoopDetection& loop, const optim::PoseGraphResult& dry_run,
                                  optim::PoseGraphResult& result, const LoopClosingParams& params) {
  const double max_m = params.pose_graph_max_edge_change_m, max_deg = params.pose_graph_max_edge_change_deg;
  const LoopGap gap = loop_gap(result.T_cw, loop);
  const optim::Fallback fallback =
      optim::fall_back_if_torn(all, pre, result.T_cw, dry_run.T_cw, max_m, max_deg);
  const optim::OdometryChange& change = fallback.change;
  const std::uint64_t current = loop.current->id(), old = loop.loop->id();
  spdlog::debug(
      "loop {}-{}: the correction moved keyframe {} by {:.3f} m / {:.1f} deg against keyframe {}, left the "
      "loop {:.3f} m / {:.2f} deg open",
      current, old, change.keyframe, change.metres, change.degrees, change.other, gap.metres, gap.degrees);
  if (fallback.taken) {
    spdlog::warn(
        "loop {}-{}: with the fusion's links the correction would {} (at most {} m / {} deg); the map takes "
        "its dry run's solution",
        current, old, change.beyond(max_m, max_deg), max_m, max_deg);
    return true;
  }
  if (gap.within(max_m, max_deg)) return false;
  optim::take_solution(result.T_cw, dry_run.T_cw);
  spdlog::warn(
      "loop {}-{}: with the fusion's links the pose graph leaves the loop {:.3f} m / {:.1f} deg open "
      "(at most {} m / {} deg); the map takes its dry run's solution",
      current, old, gap.metres, gap.degrees, max_m, max_deg);
  return true;
}
}  // namespace lrd::loop
