#pragma once
// Judging a loop's pose-graph correction (the divergence hunt, bench/results/divergence.md): the
// dry run that comes before anything moves, and the choice between the real solve and the dry run's
// solution after the fusion (loop_closer.cc, steps 3 and 6 of docs/place-recognition.md). A
// correction is plausible when it changes no keyframe's odometry by more than the limits
// (optim/odometry_change.h) and closes the loop to within them.
#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <vector>

#include "lrd/loop/loop_detector.h"
#include "lrd/map/keyframe.h"
#include "lrd/optim/odometry_change.h"
#include "lrd/optim/pose_graph_optimizer.h"

namespace lrd::map {
class Map;
}

namespace lrd::loop {

struct LoopClosingParams;

using KeyFramePoses = std::map<map::KeyFrame*, Eigen::Isometry3d, map::ById>;

// A keyframe's pose in `poses`, or its current one if it has none there.
Eigen::Isometry3d pose_in(const KeyFramePoses& poses, map::KeyFrame* k);

// How far a solution leaves the loop open: the current keyframe's pose against the loop keyframe's,
// solved against measured by the loop's matches.
using LoopGap = optim::MotionSize;
[[nodiscard]] LoopGap loop_gap(const optim::SolvedPoses& T_cw, const LoopDetection& loop);

// The dry run: the essential graph as it is, the neighbourhood at its `corrected` poses, the loop's
// edge and one from each neighbourhood keyframe to the loop keyframe (standing in for the links the
// fusion will add). Its solution, or none (with a warning) when it changes a keyframe's odometry or
// leaves the loop open beyond pose_graph_max_edge_change_m/_deg.
[[nodiscard]] std::optional<optim::PoseGraphResult> plausible_correction(
    const map::Map& map, const LoopClosingParams& params, const LoopDetection& loop,
    const KeyFramePoses& uncorrected, const KeyFramePoses& corrected, double correction_m);

// After the fusion: `result` (the real solve) stays unless it tears the odometry against `pre` or
// leaves the loop open beyond the same limits; then it takes `dry_run`'s poses (with a warning).
// Returns whether it did.
bool settle_on_plausible_solution(const std::vector<map::KeyFrame*>& all, const optim::PoseOf& pre,
                                  const LoopDetection& loop, const optim::PoseGraphResult& dry_run,
                                  optim::PoseGraphResult& result, const LoopClosingParams& params);

}  // namespace lrd::loop
