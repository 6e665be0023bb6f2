#include "lrd/mapping/local_mapper.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>

#include "lrd/geometry/triangulation.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/keyframe_database.h"
#include "lrd/map/map.h"
#include "lrd/map/map_point.h"
#include "lrd/util/fault_injection.h"
#include "lrd/util/thread_priority.h"

namespace lrd::mapping {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

LocalMapper::LocalMapper(map::Map& map, LocalMapperParams params, bool threaded)
    : map_(map),
      params_(params),
      threaded_(threaded),
      matcher_(match::MatcherParams{0.6f, false}),
      reclamation_(map.reclamation(), "local mapping") {
  if (threaded_) thread_ = std::thread([this] { run(); });
}

LocalMapper::~LocalMapper() {
  try {
    shutdown();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
  } catch (...) {
  }
}

void LocalMapper::insert_keyframe(map::KeyFrame* kf) {
  queue_.push(kf->id());
  abort_ba_.store(true);
}

std::size_t LocalMapper::queued() const {
  return queue_.size();
}

void LocalMapper::process_queued() {
  queue_.drain([this](std::uint64_t id) { process(id); });
}

void LocalMapper::shutdown() {
  if (!threaded_) {
    process_queued();
    return;
  }
  queue_.stop();
  if (thread_.joinable()) thread_.join();
  own_errors_.rethrow();
}

LocalMapperStats LocalMapper::stats() const {
  std::lock_guard lock(stats_mutex_);
  return stats_;
}

void LocalMapper::run() {
  util::name_this_thread("lrd-mapping");
  // Busy from the moment a keyframe leaves the queue (tracking asks before proposing another).
  try {
    while (const auto id = queue_.wait_pop([this] { accepting_.store(false); })) {
      process(*id);
      accepting_.store(true);
    }
  } catch (...) {
    errors_->capture("local mapping");
    accepting_.store(true);
  }
}

void LocalMapper::process(std::uint64_t keyframe_id) {
  util::check_fault_point("local_mapping");
  map::KeyFrame* kf = nullptr;
  {
    std::lock_guard lock(map_.mutex());
    // Between two keyframes this thread keeps only its recent points.
    recent_points_.remove_if([](const map::MapPoint* mp) { return mp->is_bad(); });
    reclamation_.quiescent();
    // Removed while it waited in the queue: nothing to map, nothing to hand on.
    kf = map_.keyframe(keyframe_id);
    if (kf == nullptr) return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  process_new_keyframe(kf);
  cull_recent_map_points(kf);
  create_new_map_points(kf);
  if (!has_queued()) search_in_neighbours(kf);
  abort_ba_.store(false);
  if (!has_queued()) {
    if (params_.local_ba) {
      const auto tb = std::chrono::steady_clock::now();
      // Lock-step runs never abort: the result must not depend on timing.
      const auto ba = optim::local_bundle_adjustment(kf, map_, threaded_ ? &abort_ba_ : nullptr, params_.ba);
      // Centimetres are BA's daily work; decimetres against a parent are the divergence hunt's
      // tears (bench/results/divergence.md), logged with the pair, refused beyond the limits.
      constexpr double kLoggedOdometryChangeM = 0.05;
      const optim::OdometryChange& change = ba.odometry_change;
      if (ba.implausible)
        spdlog::warn("local BA at keyframe {} rejected: it would {} (limits {} m / {} deg)", kf->id(),
                     change.beyond(params_.ba.max_odometry_change_m, params_.ba.max_odometry_change_deg),
                     params_.ba.max_odometry_change_m, params_.ba.max_odometry_change_deg);
      else if (ba.held_pairs > 0)
        spdlog::debug(
            "local BA at keyframe {}: held {} pair(s) of keyframes where they were to stay within {} m / {} "
            "deg",
            kf->id(), ba.held_pairs, params_.ba.max_odometry_change_m, params_.ba.max_odometry_change_deg);
      else if (!ba.aborted && change.metres > kLoggedOdometryChangeM)
        spdlog::debug(
            "local BA at keyframe {}: moved keyframe {} by {:.3f} m / {:.1f} deg against keyframe {}",
            kf->id(), change.keyframe, change.metres, change.degrees, change.other);
      std::lock_guard lock(stats_mutex_);
      ++stats_.bundle_adjustments;
      if (ba.aborted) ++stats_.aborted_bundle_adjustments;
      if (ba.implausible) ++stats_.implausible_bundle_adjustments;
      stats_.ba_seconds += seconds_since(tb);
    }
    if (params_.keyframe_culling) cull_keyframes(kf);
  }
  {
    std::lock_guard lock(stats_mutex_);
    ++stats_.keyframes;
    stats_.busy_seconds += seconds_since(t0);
  }
  if (keyframe_callback_) keyframe_callback_(kf);
}

void LocalMapper::process_new_keyframe(map::KeyFrame* kf) {
  // The words read only the keyframe's descriptors, fixed since tracking made it, and only this
  // thread gives a keyframe its words: transformed without holding the map (about 1 ms of the
  // 2.5 ms this step held it on walking_halfsphere, bench/results/log/performance.md), stored while
  // holding it.
  const bool indexed = vocabulary_ != nullptr && database_ != nullptr;
  data::Frame::Words words;
  if (indexed && !kf->features().has_bow()) words = kf->words(*vocabulary_);
  std::lock_guard lock(map_.mutex());
  if (kf->is_bad()) return;
  if (indexed) {
    kf->set_words(std::move(words));
    database_->add(kf);
  }
  map_.keyframe_mapped(kf);
  const auto& points = kf->map_points();
  for (std::size_t i = 0; i < points.size(); ++i) {
    map::MapPoint* mp = points[i];
    if (mp == nullptr) continue;
    if (mp->is_bad()) {  // the slot would outlive the point
      kf->erase_map_point(i);
      continue;
    }
    if (!mp->is_in_keyframe(kf)) {
      // Matched by tracking: the keyframe becomes one more observation.
      mp->add_observation(kf, i);
      mp->update_normal_and_depth();
      mp->compute_distinctive_descriptor();
    } else {
      // Created by tracking from this keyframe's depth: watch it in its first keyframes. (Or
      // matched by tracking to two keypoints: the second slot keeps it, unobserved; removing the
      // point clears every slot of its observers, map_point.cc.)
      recent_points_.push_back(mp);
    }
  }
  kf->update_connections();
}

void LocalMapper::cull_recent_map_points(map::KeyFrame* kf) {
  std::lock_guard lock(map_.mutex());
  constexpr int kMinObservations = 3;  // RGB-D (ORB-SLAM2: 2 monocular, 3 otherwise)
  const std::uint64_t current = kf->id();
  for (auto it = recent_points_.begin(); it != recent_points_.end();) {
    map::MapPoint* mp = *it;
    if (mp->is_bad()) {
      it = recent_points_.erase(it);
    } else if (mp->found_ratio() < 0.25f) {
      mp->set_bad();
      it = recent_points_.erase(it);
    } else if (current >= mp->first_keyframe_id() + 2 && mp->num_observations() <= kMinObservations) {
      mp->set_bad();
      it = recent_points_.erase(it);
    } else if (current >= mp->first_keyframe_id() + 3) {
      it = recent_points_.erase(it);
    } else {
      ++it;
    }
  }
}

void LocalMapper::create_new_map_points(map::KeyFrame* kf) {
  std::vector<map::KeyFrame*> neighbours;
  {
    std::lock_guard lock(map_.mutex());
    if (kf->is_bad()) return;
    neighbours = kf->best_covisibles(static_cast<std::size_t>(params_.triangulation_neighbours));
  }
  for (std::size_t n = 0; n < neighbours.size(); ++n) {
    if (n > 0 && has_queued()) return;  // tracking is waiting for the next keyframe
    std::lock_guard lock(map_.mutex());
    map::KeyFrame* kf2 = neighbours[n];
    if (kf->is_bad() || kf2->is_bad()) continue;
    const data::Frame& f1 = kf->features();
    const data::Frame& f2 = kf2->features();
    const camera::PinholeCamera& cam = f1.camera();
    const Eigen::Vector3d o1 = kf->camera_center(), o2 = kf2->camera_center();
    // Too short a baseline adds nothing that the depth sensor does not give already.
    if ((o2 - o1).norm() < cam.baseline()) continue;
    const Eigen::Matrix3d F12 = geometry::fundamental_matrix(kf->T_cw(), kf2->T_cw(), cam.K());
    const auto matches = matcher_.search_for_triangulation(*kf, *kf2, F12);
    const Eigen::Isometry3d T1 = kf->T_cw(), T2 = kf2->T_cw();
    const Eigen::Matrix3d R1wc = T1.rotation().transpose(), R2wc = T2.rotation().transpose();
    const float ratio_factor = 1.5f * f1.scale_factors()[1];
    std::uint64_t created = 0;
    for (const auto& [i1, i2] : matches) {
      const cv::KeyPoint& kp1 = f1.undistorted()[i1];
      const cv::KeyPoint& kp2 = f2.undistorted()[i2];
      const float ur1 = f1.u_right(i1), ur2 = f2.u_right(i2);
      const bool stereo1 = ur1 >= 0.0f, stereo2 = ur2 >= 0.0f;
      const Eigen::Vector3d xn1((kp1.pt.x - cam.cx) / cam.fx, (kp1.pt.y - cam.cy) / cam.fy, 1.0);
      const Eigen::Vector3d xn2((kp2.pt.x - cam.cx) / cam.fx, (kp2.pt.y - cam.cy) / cam.fy, 1.0);
      const Eigen::Vector3d ray1 = R1wc * xn1, ray2 = R2wc * xn2;
      const double cos_rays = ray1.dot(ray2) / (ray1.norm() * ray2.norm());
      // Parallax the depth sensor's virtual stereo pair gives each view.
      double cos_stereo1 = cos_rays + 1.0, cos_stereo2 = cos_rays + 1.0;
      if (stereo1) cos_stereo1 = std::cos(2.0 * std::atan2(cam.baseline() / 2.0, f1.depth(i1)));
      if (stereo2) cos_stereo2 = std::cos(2.0 * std::atan2(cam.baseline() / 2.0, f2.depth(i2)));
      const double cos_stereo = std::min(cos_stereo1, cos_stereo2);
      std::optional<Eigen::Vector3d> x;
      if (cos_rays < cos_stereo && cos_rays > 0.0 && (stereo1 || stereo2 || cos_rays < 0.9998)) {
        x = geometry::triangulate(xn1, T1, xn2, T2);
      } else if (stereo1 && cos_stereo1 < cos_stereo2) {
        x = T1.inverse() * cam.unproject(kp1.pt.x, kp1.pt.y, f1.depth(i1));
      } else if (stereo2 && cos_stereo2 < cos_stereo1) {
        x = T2.inverse() * cam.unproject(kp2.pt.x, kp2.pt.y, f2.depth(i2));
      }
      if (!x) continue;
      const Eigen::Vector3d p1 = T1 * *x, p2 = T2 * *x;
      if (p1.z() <= 0.0 || p2.z() <= 0.0) continue;
      // Reprojection error in both views (chi-square, 2 or 3 dof).
      auto reprojection_ok = [&](const Eigen::Vector3d& p, const cv::KeyPoint& kp, float ur, bool stereo,
                                 const data::Frame& f) {
        const double inv_s2 = f.inv_level_sigma2()[static_cast<std::size_t>(kp.octave)];
        return cam.reprojection_chi2(p, kp.pt.x, kp.pt.y, stereo ? ur : -1.0, inv_s2) <=
               (stereo ? 7.8 : 5.991);
      };
      if (!reprojection_ok(p1, kp1, ur1, stereo1, f1) || !reprojection_ok(p2, kp2, ur2, stereo2, f2))
        continue;
      // Scale consistency: the distance ratio must agree with the pyramid-level ratio.
      const double dist1 = (*x - o1).norm(), dist2 = (*x - o2).norm();
      if (dist1 == 0.0 || dist2 == 0.0) continue;
      const double ratio_dist = dist2 / dist1;
      const double ratio_octave = f1.scale_factors()[static_cast<std::size_t>(kp1.octave)] /
                                  f2.scale_factors()[static_cast<std::size_t>(kp2.octave)];
      if (ratio_dist * ratio_factor < ratio_octave || ratio_dist > ratio_octave * ratio_factor) continue;

      map::MapPoint* mp = map_.create_map_point(*x, kf, kf->frame_id());
      mp->add_observation(kf, i1);
      mp->add_observation(kf2, i2);
      kf->add_map_point(mp, i1);
      kf2->add_map_point(mp, i2);
      mp->compute_distinctive_descriptor();
      mp->update_normal_and_depth();
      recent_points_.push_back(mp);
      ++created;
    }
    std::lock_guard slock(stats_mutex_);
    stats_.triangulated_points += created;
  }
}

void LocalMapper::search_in_neighbours(map::KeyFrame* kf) {
  // Step by step, each under its own hold of the map mutex: tracking waits for one neighbour's fuse
  // at most, not for all of them (one hold of ~4 ms per keyframe on walking_halfsphere, tum
  // realism: bench/results/log/performance.md). Each step checks again what may have turned bad
  // meanwhile, as create_new_map_points does; lock-step (deterministic) runs take the same steps in
  // order.
  const std::uint64_t tag = kf->id();
  std::vector<map::KeyFrame*> targets;
  {
    std::lock_guard lock(map_.mutex());
    if (kf->is_bad()) return;
    for (map::KeyFrame* n : kf->best_covisibles(static_cast<std::size_t>(params_.fuse_neighbours))) {
      if (n->is_bad() || n->fuse_target_for_kf == tag) continue;
      n->fuse_target_for_kf = tag;
      targets.push_back(n);
    }
    const std::size_t first_order = targets.size();
    for (std::size_t i = 0; i < first_order; ++i) {
      for (map::KeyFrame* n2 :
           targets[i]->best_covisibles(static_cast<std::size_t>(params_.fuse_second_neighbours))) {
        if (n2->is_bad() || n2->fuse_target_for_kf == tag || n2 == kf) continue;
        n2->fuse_target_for_kf = tag;
        targets.push_back(n2);
      }
    }
  }
  // The new keyframe's points into the neighbours ...
  int fused_out = 0;
  for (map::KeyFrame* t : targets) {
    std::lock_guard lock(map_.mutex());
    if (kf->is_bad()) return;
    if (!t->is_bad()) fused_out += matcher_.fuse(*t, kf->map_points());
  }
  // ... and the neighbours' points into the new keyframe.
  std::lock_guard lock(map_.mutex());
  if (kf->is_bad()) return;
  std::vector<map::MapPoint*> candidates;
  for (map::KeyFrame* t : targets) {
    if (t->is_bad()) continue;
    for (map::MapPoint* mp : t->map_points()) {
      if (mp == nullptr || mp->is_bad() || mp->fuse_candidate_for_kf == tag) continue;
      mp->fuse_candidate_for_kf = tag;
      candidates.push_back(mp);
    }
  }
  const int fused_in = matcher_.fuse(*kf, candidates);
  spdlog::debug("keyframe {}: fused {} points into {} neighbours, {} of {} candidates into it", kf->id(),
                fused_out, targets.size(), fused_in, candidates.size());
  for (map::MapPoint* mp : kf->map_points()) {
    if (mp == nullptr || mp->is_bad()) continue;
    mp->compute_distinctive_descriptor();
    mp->update_normal_and_depth();
  }
  kf->update_connections();
}

void LocalMapper::cull_keyframes(map::KeyFrame* kf) {
  std::lock_guard lock(map_.mutex());
  if (kf->is_bad()) return;
  const std::vector<map::KeyFrame*> local = kf->ordered_covisibles();
  std::uint64_t culled = 0;
  for (map::KeyFrame* k2 : local) {
    if (k2->id() == 0 || k2->is_bad()) continue;
    const CullingDecision d = judge_redundancy(*k2, kf->id(), params_.culling);
    if (!d.cull) continue;
    k2->set_bad();  // refused for a keyframe on a loop edge or examined by loop closing
    if (!k2->is_bad()) continue;
    // Indexed here, so dropped from the index here: it may be freed once every thread let go.
    if (database_ != nullptr) database_->erase(k2);
    ++culled;
    if (d.same_place != nullptr)
      spdlog::debug("keyframe {} culled: at the place of keyframe {}, {} of {} close points seen by others",
                    k2->id(), d.same_place->id(), d.points.redundant, d.points.close_points);
  }
  std::lock_guard slock(stats_mutex_);
  stats_.culled_keyframes += culled;
}

}  // namespace lrd::mapping
