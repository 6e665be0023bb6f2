#include "lrd/optim/local_bundle_adjuster.h"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/map/map_point.h"
#include "lrd/optim/ba_problem.h"

namespace lrd::optim {

LocalBundleAdjustmentStats local_bundle_adjustment(map::KeyFrame* keyframe, map::Map& map,
                                                   const std::atomic<bool>* abort,
                                                   const LocalBundleAdjustmentParams& params) {
  LocalBundleAdjustmentStats stats;
  std::vector<map::KeyFrame*> kfs;  // local ones first, then fixed ones
  std::vector<map::MapPoint*> mps;
  std::vector<PoseBlock> poses;
  std::vector<PointBlock> points;
  std::vector<Observation> obs;
  std::size_t n_local = 0;
  Intrinsics k{};
  std::uint64_t change_index = 0;
  {
    std::lock_guard lock(map.mutex());
    if (keyframe->is_bad()) return stats;
    change_index = map.big_change_index();
    const camera::PinholeCamera& cam = keyframe->features().camera();
    k = {cam.fx, cam.fy, cam.cx, cam.cy, cam.bf, cam.disparity_sigma};
    const std::uint64_t tag = keyframe->id();
    kfs.push_back(keyframe);
    keyframe->local_ba_for_kf = tag;
    const auto neighbours =
        params.max_local_keyframes > 0
            ? keyframe->best_covisibles(static_cast<std::size_t>(params.max_local_keyframes))
            : keyframe->ordered_covisibles();
    for (map::KeyFrame* kf : neighbours) {
      if (kf->is_bad() || kf->local_ba_for_kf == tag) continue;
      kf->local_ba_for_kf = tag;
      kfs.push_back(kf);
    }
    n_local = kfs.size();
    for (std::size_t i = 0; i < n_local; ++i) {
      for (map::MapPoint* mp : kfs[i]->map_points()) {
        if (mp == nullptr || mp->is_bad() || mp->local_ba_for_kf == tag) continue;
        mp->local_ba_for_kf = tag;
        mps.push_back(mp);
      }
    }
    // Deterministic layout whatever the neighbour order: points by id.
    std::sort(mps.begin(), mps.end(), map::ById{});
    for (map::MapPoint* mp : mps)
      for (const auto& [kf, idx] : mp->observations())
        if (!kf->is_bad() && kf->local_ba_for_kf != tag && kf->fixed_ba_for_kf != tag) {
          kf->fixed_ba_for_kf = tag;
          kfs.push_back(kf);
        }
    std::sort(kfs.begin() + static_cast<long>(n_local), kfs.end(), map::ById{});
    for (map::KeyFrame* kf : kfs) poses.push_back(to_block(kf->T_cw()));
    std::map<const map::KeyFrame*, std::size_t> index;
    for (std::size_t i = 0; i < kfs.size(); ++i) index[kfs[i]] = i;
    for (std::size_t p = 0; p < mps.size(); ++p) {
      const Eigen::Vector3d& x = mps[p]->position();
      points.push_back({x.x(), x.y(), x.z()});
      for (const auto& [kf, idx] : mps[p]->observations()) {
        const auto it = index.find(kf);
        if (it == index.end()) continue;
        obs.push_back(make_observation(it->second, p, kf->features(), idx));
      }
    }
  }
  stats.local_keyframes = static_cast<int>(n_local);
  stats.fixed_keyframes = static_cast<int>(kfs.size() - n_local);
  stats.points = static_cast<int>(mps.size());
  stats.observations = static_cast<int>(obs.size());
  if (obs.empty()) return stats;
  // Keyframe 0 defines the world frame: never move it (swap it to the end of the local range,
  // which makes it the first fixed one).
  for (std::size_t i = 0; i < n_local; ++i) {
    if (kfs[i]->id() != 0) continue;
    const std::size_t last = n_local - 1;
    std::swap(kfs[i], kfs[last]);
    std::swap(poses[i], poses[last]);
    for (Observation& o : obs) {
      if (o.kf == i)
        o.kf = last;
      else if (o.kf == last)
        o.kf = i;
    }
    --n_local;
    break;
  }
  stats.initial_rms_px = rms(k, poses, points, obs);

  BaSolveOptions opts;
  opts.chi2_mono = params.chi2_mono;
  opts.chi2_stereo = params.chi2_stereo;
  opts.abort = abort;
  opts.iterations = params.first_iterations;
  if (!solve(k, poses, n_local, points, obs, opts)) stats.aborted = true;
  if (!stats.aborted) {
    classify_outliers(k, poses, points, obs, params.chi2_mono, params.chi2_stereo);
    opts.robust = false;
    opts.iterations = params.second_iterations;
    if (!solve(k, poses, n_local, points, obs, opts)) stats.aborted = true;
  }
  // Final classification on the result (ORB-SLAM2 also erases these after an aborted round).
  classify_outliers(k, poses, points, obs, params.chi2_mono, params.chi2_stereo);
  stats.final_rms_px = rms(k, poses, points, obs);

  std::lock_guard lock(map.mutex());
  if (map.big_change_index() != change_index) {
    // A loop closure or global BA moved the map while this solved: its poses are stale.
    stats.aborted = true;
    return stats;
  }
  for (const Observation& o : obs) {
    if (!o.outlier) continue;
    ++stats.outliers;
    map::KeyFrame* kf = kfs[o.kf];
    map::MapPoint* mp = mps[o.point];
    kf->erase_map_point(mp);  // its slot, and a second one if tracking matched it twice
    mp->erase_observation(kf);
  }
  std::unordered_map<const map::KeyFrame*, Eigen::Isometry3d> solved;
  for (std::size_t i = 0; i < n_local; ++i) solved.emplace(kfs[i], from_block(poses[i]));
  stats.odometry_change = largest_odometry_change(
      kfs, [](map::KeyFrame* kf) { return kf->T_cw(); },
      [&](map::KeyFrame* kf) {
        const auto it = solved.find(kf);
        return it != solved.end() ? it->second : kf->T_cw();
      });
  for (std::size_t i = 0; i < n_local; ++i)
    if (!kfs[i]->is_bad()) kfs[i]->set_pose(solved.at(kfs[i]));
  for (std::size_t p = 0; p < mps.size(); ++p) {
    if (mps[p]->is_bad()) continue;
    mps[p]->set_position(Eigen::Vector3d(points[p][0], points[p][1], points[p][2]));
    mps[p]->update_normal_and_depth();
  }
  return stats;
}

}  // namespace lrd::optim
