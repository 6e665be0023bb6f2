#pragma once
// Local bundle adjustment (ORB-SLAM2's LocalBundleAdjustment, paper §2.2), on Ceres: the poses of
// a keyframe and its covisible keyframes and every map point they see are refined jointly; the
// other keyframes observing those points stay fixed and anchor the gauge. Two rounds: a few
// iterations with a Huber kernel, then, with outliers (chi-square above 5.991 / 7.815, or behind
// the camera) left out, more iterations without it; finally the outlier observations are erased.
//
// Only the reading of the problem and the write-back hold Map::mutex(); the solve runs unlocked,
// so tracking goes on meanwhile. An `abort` flag stops the solve (a new keyframe arrived).
#include <atomic>

#include "lrd/optim/odometry_change.h"

namespace lrd::map {
class KeyFrame;
class Map;
}  // namespace lrd::map

namespace lrd::optim {

struct LocalBundleAdjustmentParams {
  int first_iterations = 5;
  int second_iterations = 10;
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  int max_local_keyframes = 0;  // 0: every covisible keyframe (ORB-SLAM2)
  // A result that changes a keyframe's pose against its parent or a tracking-linked keyframe by
  // more (or takes a linked pair further from its tracked odometry, odometry_change.h) is BA
  // pulling keyframes onto wrongly fused points, not a drift being removed (the divergence hunt,
  // bench/results/divergence.md; the loop closer's limits): solved again with that pair held,
  // refused (nothing written) beyond max_held_pairs pairs.
  double max_odometry_change_m = 0.25;
  double max_odometry_change_deg = 10.0;
  int max_held_pairs = 2;
};

struct LocalBundleAdjustmentStats {
  int local_keyframes = 0;
  int fixed_keyframes = 0;
  int points = 0;
  int observations = 0;
  int outliers = 0;
  double initial_rms_px = 0.0;  // weighted reprojection error before and after
  double final_rms_px = 0.0;
  bool aborted = false;
  bool implausible = false;  // beyond the odometry change limits: solved, not written
  int held_pairs = 0;        // pairs held where they were and solved again, to stay within them
  // The result against the poses it replaced: each local keyframe relative to its parent and its
  // tracking-linked keyframes (odometry_change.h). Local mapping logs it (the divergence hunt) and
  // warns when it made the result implausible.
  OdometryChange odometry_change;
};

LocalBundleAdjustmentStats local_bundle_adjustment(map::KeyFrame* keyframe, map::Map& map,
                                                   const std::atomic<bool>* abort = nullptr,
                                                   const LocalBundleAdjustmentParams& params = {});

}  // namespace lrd::optim
