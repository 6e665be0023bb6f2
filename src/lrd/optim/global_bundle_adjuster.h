#pragma once
// Global bundle adjustment (ORB-SLAM2's RunGlobalBundleAdjustment, after a loop closure): every
// keyframe pose (keyframe 0 fixed: it defines the world) and every map point refined jointly,
// with a Huber kernel.
//
// Tracking and local mapping go on meanwhile: the map is read under Map::mutex(), solved without
// it, and merged back under it. Keyframes and points created during the solve are corrected
// through the spanning tree (a keyframe moves with its parent; a point with its reference
// keyframe), as ORB-SLAM2 does.
#include <atomic>
#include <cstdint>

#include "lrd/optim/odometry_change.h"

namespace lrd::map {
class Map;
}

namespace lrd::optim {

struct GlobalBundleAdjustmentParams {
  int iterations = 10;
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  // Plausibility (the divergence hunt, bench/results/divergence.md): global BA refines a map the
  // pose graph has already made consistent; it moves a keyframe against its spanning-tree parent by
  // millimetres. A result that moves one by more than this has found another minimum, pulled by
  // structure that is not rigid (points on people kept by `static` mode: rms 4-6 px there against
  // 0.6 px on a static scene), and would tear the trajectory apart (jumps of 0.5-1.2 m between
  // consecutive frames on walking_xyz). It is not merged.
  double max_edge_change_m = 0.1;
  double max_edge_change_deg = 5.0;
};

struct GlobalBundleAdjustmentStats {
  int keyframes = 0;
  int points = 0;
  int observations = 0;
  int propagated_keyframes = 0;  // created during the solve, corrected through the spanning tree
  double initial_rms_px = 0.0;
  double final_rms_px = 0.0;
  bool aborted = false;      // stopped by `abort` (a new loop): nothing was merged
  bool implausible = false;  // a keyframe moved too far against its parent or a linked one: nothing merged
  // Over the odometry pairs among the solved keyframes (optim/odometry_change.h).
  OdometryChange odometry_change;
};

// `run` tags the keyframes this run optimizes (distinct per call).
GlobalBundleAdjustmentStats global_bundle_adjustment(map::Map& map, std::uint64_t run,
                                                     const std::atomic<bool>* abort = nullptr,
                                                     const GlobalBundleAdjustmentParams& params = {});

}  // namespace lrd::optim
