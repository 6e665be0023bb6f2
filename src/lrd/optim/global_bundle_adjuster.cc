#include "lrd/optim/global_bundle_adjuster.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <mutex>
#include <vector>

#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/map/map_point.h"
#include "lrd/optim/ba_problem.h"
#include "lrd/optim/odometry_change.h"

namespace lrd::optim {

GlobalBundleAdjustmentStats global_bundle_adjustment(map::Map& map, std::uint64_t run,
                                                     const std::atomic<bool>* abort,
                                                     const GlobalBundleAdjustmentParams& params) {
  GlobalBundleAdjustmentStats stats;
  std::vector<map::KeyFrame*> kfs;
  std::vector<map::MapPoint*> mps;
  std::vector<PoseBlock> poses;
  std::vector<PointBlock> points;
  std::vector<Observation> obs;
  Intrinsics k{};
  std::uint64_t change_index = 0;
  std::map<const map::KeyFrame*, std::size_t> index;  // keyframe -> its pose block
  {
    std::lock_guard lock(map.mutex());
    change_index = map.big_change_index();
    kfs = map.keyframes();  // id order: keyframe 0 first
    if (kfs.size() < 2) return stats;
    const camera::PinholeCamera& cam = kfs.front()->features().camera();
    k = {cam.fx, cam.fy, cam.cx, cam.cy, cam.bf, cam.disparity_sigma};
    // Keyframe 0 last, so that it is the one fixed pose block.
    std::rotate(kfs.begin(), kfs.begin() + 1, kfs.end());
    for (std::size_t i = 0; i < kfs.size(); ++i) {
      index[kfs[i]] = i;
      poses.push_back(to_block(kfs[i]->T_cw()));
    }
    for (map::MapPoint* mp : map.map_points()) {
      const std::size_t first = obs.size();
      const std::size_t p = mps.size();
      for (const auto& [kf, idx] : mp->observations()) {
        const auto it = index.find(kf);
        if (it == index.end()) continue;
        obs.push_back(make_observation(it->second, p, kf->features(), idx));
      }
      if (obs.size() - first < 2) {  // one view does not constrain a point jointly with poses
        obs.resize(first);
        continue;
      }
      mps.push_back(mp);
      const Eigen::Vector3d& x = mp->position();
      points.push_back({x.x(), x.y(), x.z()});
    }
  }
  stats.keyframes = static_cast<int>(kfs.size());
  stats.points = static_cast<int>(mps.size());
  stats.observations = static_cast<int>(obs.size());
  if (obs.empty()) return stats;
  stats.initial_rms_px = rms(k, poses, points, obs);
  BaSolveOptions opts;
  opts.chi2_mono = params.chi2_mono;
  opts.chi2_stereo = params.chi2_stereo;
  opts.iterations = params.iterations;
  opts.linear_solver = ceres::SPARSE_SCHUR;
  opts.abort = abort;
  const std::vector<PoseBlock> initial_poses = poses;
  if (!solve(k, poses, kfs.size() - 1, points, obs, opts)) {
    stats.aborted = true;
    return stats;
  }
  stats.final_rms_px = rms(k, poses, points, obs);

  std::lock_guard lock(map.mutex());
  if (map.big_change_index() != change_index) {
    // Another loop correction happened meanwhile: this result predates it.
    stats.aborted = true;
    return stats;
  }
  // Only keyframes the problem constrained take its result; one without observations (still
  // queued for local mapping when the map was read) follows its parent below, or keeps its pose.
  std::vector<bool> observed(kfs.size(), false);
  for (const Observation& o : obs) observed[o.kf] = true;
  // How far the solve moved each solved keyframe against its solved parent and linked keyframes.
  stats.odometry_change = largest_odometry_change(
      kfs, [&](map::KeyFrame* kf) { return from_block(initial_poses[index.at(kf)]); },
      [&](map::KeyFrame* kf) { return from_block(poses[index.at(kf)]); },
      [&](const map::KeyFrame* kf) {
        const auto it = index.find(kf);
        return it != index.end() && observed[it->second];
      });
  if (!stats.odometry_change.within(params.max_edge_change_m, params.max_edge_change_deg)) {
    stats.implausible = true;
    return stats;
  }
  for (std::size_t i = 0; i < kfs.size(); ++i) {
    if (!observed[i]) continue;
    kfs[i]->T_cw_global_ba = from_block(poses[i]);
    kfs[i]->global_ba_for = run;
  }
  // Keyframes created during the solve follow their parents (breadth-first from the root).
  std::deque<map::KeyFrame*> queue = {map.first_keyframe()};
  while (!queue.empty()) {
    map::KeyFrame* kf = queue.front();
    queue.pop_front();
    if (kf == nullptr) continue;
    for (map::KeyFrame* child : kf->children()) {
      if (child->global_ba_for != run) {
        child->T_cw_global_ba = child->T_cw() * kf->T_cw().inverse() * kf->T_cw_global_ba;
        child->global_ba_for = run;
        ++stats.propagated_keyframes;
      }
      queue.push_back(child);
    }
  }
  for (map::KeyFrame* kf : map.keyframes()) {
    if (kf->global_ba_for != run) continue;  // not reachable in the tree (cannot happen for a healthy map)
    kf->T_cw_before_global_ba = kf->T_cw();
    kf->set_pose(kf->T_cw_global_ba);
  }
  for (std::size_t p = 0; p < mps.size(); ++p) {
    if (mps[p]->is_bad()) continue;
    mps[p]->set_position(Eigen::Vector3d(points[p][0], points[p][1], points[p][2]));
  }
  // Points not in the problem move rigidly with their reference keyframe.
  std::vector<map::MapPoint*> in_problem = mps;
  std::sort(in_problem.begin(), in_problem.end());
  for (map::MapPoint* mp : map.map_points()) {
    if (std::binary_search(in_problem.begin(), in_problem.end(), mp)) {
      mp->update_normal_and_depth();
      continue;
    }
    const map::KeyFrame* ref = mp->reference_keyframe();
    if (ref == nullptr || ref->global_ba_for != run) continue;
    mp->set_position(ref->T_cw().inverse() * (ref->T_cw_before_global_ba * mp->position()));
    mp->update_normal_and_depth();
  }
  map.notify_big_change();
  return stats;
}

}  // namespace lrd::optim
