#include "lrd/loop/loop_closer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <set>

#include "lrd/loop/essential_graph.h"
#include "lrd/loop/loop_agreement.h"
#include "lrd/loop/loop_solution.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/keyframe_database.h"
#include "lrd/map/map.h"
#include "lrd/map/map_point.h"
#include "lrd/mapping/local_mapper.h"
#include "lrd/match/orb_matcher.h"
#include "lrd/optim/pose_graph_optimizer.h"
#include "lrd/util/fault_injection.h"
#include "lrd/util/thread_priority.h"

namespace lrd::loop {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

LoopCloser::LoopCloser(map::Map& map, map::KeyFrameDatabase& database, mapping::LocalMapper& mapper,
                       LoopClosingParams params, bool threaded)
    : map_(map),
      database_(database),
      mapper_(mapper),
      params_(std::move(params)),
      threaded_(threaded),
      detector_(database, params_.detector),
      reclamation_(map.reclamation(), "loop closing") {
  if (threaded_) thread_ = std::thread([this] { run(); });
}

LoopCloser::~LoopCloser() {
  try {
    shutdown();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
  } catch (...) {
  }
}

void LoopCloser::insert_keyframe(map::KeyFrame* kf) {
  queue_.push({kf->id(), false, {}});
}

void LoopCloser::suggest_loop(const SuggestedLoop& loop) {
  queue_.push({loop.keyframe_id, true, loop});
}

void LoopCloser::process_queued() {
  queue_.drain([this](const Work& work) { process(work); });
}

void LoopCloser::shutdown() {
  if (threaded_) {
    queue_.stop();
    if (thread_.joinable()) thread_.join();
  } else {
    process_queued();
  }
  // A running global BA finishes: the saved trajectory should have it.
  if (global_ba_thread_.joinable()) global_ba_thread_.join();
  own_errors_.rethrow();
}

LoopCloserStats LoopCloser::stats() const {
  std::lock_guard lock(stats_mutex_);
  return stats_;
}

void LoopCloser::run() {
  util::name_this_thread("lrd-loop");
  try {
    while (const auto work = queue_.wait_pop()) process(*work);
  } catch (...) {
    errors_->capture("loop closing");
  }
}

std::optional<LoopDetection> LoopCloser::find_loop(map::KeyFrame* kf, const Work& work) {
  if (!work.suggested) return detector_.detect(kf);
  map::KeyFrame* loop_kf = map_.keyframe(work.loop.loop_keyframe_id);
  // Stale (a loop was closed at it since), or the same copy: nothing to merge, nothing to count.
  if (loop_kf == nullptr || detector_.closed_since(kf) || kf->weight(loop_kf) > 0) return std::nullopt;
  return detector_.verify_suggested(kf, loop_kf, work.loop.T_cw_guess);
}

void LoopCloser::process(const Work& work) {
  util::check_fault_point("loop_closing");
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<LoopEvent> event;
  {
    std::lock_guard lock(map_.mutex());
    // Between two keyframes this thread keeps no map pointers (the detector keeps ids).
    reclamation_.quiescent();
    map::KeyFrame* kf = map_.keyframe(work.keyframe_id);
    if (kf == nullptr) return;
    // Protected from culling while it is examined (ORB-SLAM2's SetNotErase).
    kf->set_not_erase(true);
    try {
      const auto loop = find_loop(kf, work);
      if (loop && loop->T_cw_corrected.matrix().allFinite()) {
        const double detection_seconds = seconds_since(t0);
        const auto t1 = std::chrono::steady_clock::now();
        event = correct_loop(*loop);
        if (event) {
          event->detection_seconds = detection_seconds;
          event->correction_seconds = seconds_since(t1);
          event->suggested = work.suggested;
          detector_.loop_closed(kf);
        } else {
          std::lock_guard slock(stats_mutex_);
          ++stats_.rejected_loops;
        }
      }
    } catch (...) {
      // Never out of this thread (std::terminate): the map keeps what was corrected so far,
      // local BA learns that it changed, and the run ends with this error.
      map_.notify_big_change();
      kf->set_not_erase(false);
      throw;
    }
    if (kf->loop_edges().empty()) kf->set_not_erase(false);
  }
  {
    std::lock_guard lock(stats_mutex_);
    stats_.seconds += seconds_since(t0);
    if (event) stats_.loops.push_back(*event);
  }
  if (event) {
    spdlog::info("loop closed: frame {} (keyframe {}) matches keyframe {} with {} inliers; moved {:.3f} m{}",
                 event->frame_id, event->keyframe_id, event->loop_keyframe_id, event->inliers,
                 event->correction_m, event->suggested ? " (suggested by a relocalization)" : "");
    if (loop_callback_) loop_callback_(*event);
    if (params_.global_ba) start_global_ba(event->keyframe_id);
  }
}

std::optional<LoopEvent> LoopCloser::correct_loop(const LoopDetection& loop) {
  map::KeyFrame* kf = loop.current;
  const std::uint64_t tag = kf->id();
  LoopEvent event;
  event.frame_id = kf->frame_id();
  event.timestamp = kf->timestamp();
  event.keyframe_id = kf->id();
  event.loop_keyframe_id = loop.loop->id();
  event.inliers = loop.match_count;
  event.correction_m = (kf->camera_center() - loop.T_cw_corrected.inverse().translation()).norm();

  // 1. The current keyframe's neighbourhood moves rigidly with it.
  kf->update_connections();
  std::vector<map::KeyFrame*> connected = kf->ordered_covisibles();
  connected.push_back(kf);
  // Keyframes still queued for local mapping (threaded runs: tracking adds them to the map at
  // once, mapping connects them later) have no edges yet; they are the newest, taken next to the
  // current one, so they move with it, here and through the pose graph.
  std::vector<map::KeyFrame*> followers;
  for (map::KeyFrame* k : map_.keyframes())
    if (k->parent() == nullptr && k != map_.first_keyframe() && k != kf &&
        std::find(connected.begin(), connected.end(), k) == connected.end()) {
      followers.push_back(k);
      connected.push_back(k);
    }
  std::sort(connected.begin(), connected.end(), map::ById{});
  if (!agrees_with_map(loop, connected, event.correction_m)) return std::nullopt;
  KeyFramePoses uncorrected, corrected;
  const Eigen::Isometry3d T_wc_kf = kf->T_wc();
  for (map::KeyFrame* k : connected) {
    uncorrected[k] = k->T_cw();
    corrected[k] = k == kf ? loop.T_cw_corrected : k->T_cw() * T_wc_kf * loop.T_cw_corrected;
  }
  const std::optional<optim::PoseGraphResult> dry_run =
      plausible_correction(map_, params_, loop, uncorrected, corrected, event.correction_m);
  if (!dry_run) return std::nullopt;
  mapper_.interrupt_ba();
  for (map::KeyFrame* k : connected) k->loop_query_for_kf = tag;
  for (map::KeyFrame* k : connected) {
    const Eigen::Isometry3d move = corrected[k].inverse() * uncorrected[k];
    for (map::MapPoint* mp : k->map_points()) {
      if (mp == nullptr || mp->is_bad() || mp->loop_corrected_for == tag) continue;
      mp->set_position(move * mp->position());
      mp->loop_corrected_for = tag;
      mp->loop_corrected_by = k;
    }
  }
  for (map::KeyFrame* k : connected) k->set_pose(corrected[k]);
  for (map::KeyFrame* k : connected)
    for (map::MapPoint* mp : k->map_points())
      if (mp != nullptr && !mp->is_bad()) mp->update_normal_and_depth();

  // 2. The loop's matches replace the current keyframe's points; the loop side's points are fused
  //    into the whole neighbourhood.
  for (std::size_t i = 0; i < loop.matches.size(); ++i) {
    map::MapPoint* loop_mp = loop.matches[i];
    if (loop_mp == nullptr || loop_mp->is_bad()) continue;
    map::MapPoint* current = kf->map_point(i);
    if (current == loop_mp) continue;
    if (current != nullptr && !current->is_bad()) {
      current->replace(loop_mp);
    } else if (!loop_mp->is_in_keyframe(kf)) {
      kf->add_map_point(loop_mp, i);
      loop_mp->add_observation(kf, i);
      loop_mp->compute_distinctive_descriptor();
    }
  }
  const match::OrbMatcher fuser({0.8f, false});
  for (map::KeyFrame* k : connected)
    if (!k->is_bad()) fuser.fuse(*k, loop.loop_points, 4.0f);

  // New links across the loop: neighbours each keyframe gains by the fusion.
  std::map<map::KeyFrame*, std::set<map::KeyFrame*, map::ById>, map::ById> loop_connections;
  for (map::KeyFrame* k : connected) {
    if (k->is_bad()) continue;
    const auto before = k->ordered_covisibles();
    k->update_connections();
    for (map::KeyFrame* n : k->ordered_covisibles())
      if (n->loop_query_for_kf != tag && std::find(before.begin(), before.end(), n) == before.end())
        loop_connections[k].insert(n);
  }

  // 3. Essential-graph optimization; the loop keyframe anchors the gauge (ORB-SLAM2).
  const std::vector<map::KeyFrame*> all = map_.keyframes();
  KeyFramePoses before;  // poses before the optimization (corrected ones for the neighbourhood)
  for (map::KeyFrame* k : all) before[k] = k->T_cw();
  // Odometry-like edges are measured with the poses before the correction: the drift they
  // contain is what the optimization spreads along the loop.
  const optim::PoseOf pre = [&](map::KeyFrame* k) { return pose_in(uncorrected, k); };
  EssentialGraph graph;
  // The loop itself first, at the pose the loop measured.
  graph.add_edge(kf, loop.loop, loop.loop->T_cw() * loop.T_cw_corrected.inverse());
  for (const auto& [k, links] : loop_connections)
    for (map::KeyFrame* n : links) {
      if (n->is_bad()) continue;
      const bool main_link = (k == kf && n == loop.loop);
      if (!main_link && k->weight(n) < params_.essential_min_weight) continue;
      graph.add_edge(k, n, n->T_cw() * k->T_cw().inverse());
    }
  graph.add_map_edges(all, pre, params_.essential_min_weight);
  optim::PoseGraphResult result = graph.solve(
      all, [&](map::KeyFrame* k) { return before.at(k); }, loop.loop, params_.pose_graph_iterations);
  event.keyframes = all.size();
  event.pose_graph_edges = graph.edges.size();
  event.dry_run_solution = settle_on_plausible_solution(all, pre, loop, *dry_run, result, params_);
  for (map::KeyFrame* k : all) k->set_pose(result.T_cw.at(k->id()));
  // Followers (no edges) keep their place relative to the current keyframe.
  for (map::KeyFrame* k : followers) k->set_pose(before.at(k) * before.at(kf).inverse() * kf->T_cw());
  // Every point follows the keyframe it was corrected with (or its reference keyframe).
  for (map::MapPoint* mp : map_.map_points()) {
    map::KeyFrame* ref = mp->loop_corrected_for == tag ? mp->loop_corrected_by : mp->reference_keyframe();
    if (ref == nullptr) continue;
    const auto it = before.find(ref);
    if (it == before.end()) continue;  // reference removed: leave the point
    mp->set_position(ref->T_cw().inverse() * (it->second * mp->position()));
    mp->update_normal_and_depth();
  }
  kf->add_loop_edge(loop.loop);
  loop.loop->add_loop_edge(kf);
  map_.notify_big_change();
  spdlog::debug("loop {}-{}: {} connected keyframes, {} essential edges, pose graph cost {:.4g} -> {:.4g}",
                kf->id(), loop.loop->id(), connected.size(), graph.edges.size(), result.initial_cost,
                result.final_cost);
  return event;
}

bool LoopCloser::agrees_with_map(const LoopDetection& loop, const std::vector<map::KeyFrame*>& neighbourhood,
                                 double correction_m) const {
  const std::uint64_t current = loop.current->id(), old = loop.loop->id();
  if (std::find(neighbourhood.begin(), neighbourhood.end(), loop.loop) != neighbourhood.end()) {
    spdlog::warn("loop {}-{} rejected: keyframe {} is a covisible neighbour of keyframe {} already", current,
                 old, old, current);
    return false;
  }
  const LoopAgreement a =
      measure_loop_agreement(neighbourhood, *loop.loop, loop.T_cw_corrected.inverse() * loop.current->T_cw());
  if (!a.contradicts()) return true;
  spdlog::warn(
      "loop {}-{} rejected: its correction ({:.3f} m) contradicts the map: keyframe {} sees {} points of "
      "keyframe "
      "{}'s neighbourhood at a median {:.1f} px, {:.1f} px after the correction",
      current, old, correction_m, old, a.shared, current, a.median_before_px, a.median_after_px);
  return false;
}

}  // namespace lrd::loop
