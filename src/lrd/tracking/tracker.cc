#include "lrd/tracking/tracker.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>

#include "lrd/geometry/se3.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/map/map_point.h"
#include "lrd/mapping/local_mapper.h"
#include "lrd/match/frustum.h"
#include "lrd/tracking/rolling_shutter.h"

namespace lrd::tracking {

namespace {
// Drops the matches the pose optimization rejected (they are not searched again in this search
// pass, `tag`) and counts the map points left that keyframes observe.
int discard_outliers(data::Frame& frame, std::uint64_t tag) {
  int in_map = 0;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    map::MapPoint* mp = frame.map_points[i];
    if (mp == nullptr) continue;
    if (frame.outliers[i]) {
      frame.map_points[i] = nullptr;
      frame.outliers[i] = false;
      mp->track.in_view = false;
      mp->track.last_frame_seen = tag;
    } else if (mp->num_observations() > 0) {
      ++in_map;
    }
  }
  return in_map;
}
}  // namespace

TrackerParams TrackerParams::from_config(config::NodeReader r) {
  TrackerParams p;
  p.init_min_features = r.get("init_min_features", p.init_min_features);
  r.check(p.init_min_features >= 10, "init_min_features", "must be >= 10");
  p.motion_model_radius = r.get("motion_model_radius", p.motion_model_radius);
  r.check(p.motion_model_radius > 0 && p.motion_model_radius <= 1000, "motion_model_radius",
          "must be in (0, 1000]");
  p.min_motion_matches = r.get("min_motion_matches", p.min_motion_matches);
  r.check(p.min_motion_matches >= 0, "min_motion_matches", "must be >= 0");
  p.min_reference_matches = r.get("min_reference_matches", p.min_reference_matches);
  r.check(p.min_reference_matches >= 0, "min_reference_matches", "must be >= 0");
  p.min_pose_inliers = r.get("min_pose_inliers", p.min_pose_inliers);
  r.check(p.min_pose_inliers >= 0, "min_pose_inliers", "must be >= 0");
  p.min_local_map_inliers = r.get("min_local_map_inliers", p.min_local_map_inliers);
  r.check(p.min_local_map_inliers >= 0, "min_local_map_inliers", "must be >= 0");
  p.max_local_keyframes = r.get("max_local_keyframes", p.max_local_keyframes);
  r.check(p.max_local_keyframes >= 1, "max_local_keyframes", "must be >= 1");
  p.local_map_radius = r.get("local_map_radius", p.local_map_radius);
  r.check(p.local_map_radius > 0 && p.local_map_radius <= 1000, "local_map_radius", "must be in (0, 1000]");
  p.max_frames_between_keyframes = r.get("max_frames_between_keyframes", p.max_frames_between_keyframes);
  r.check(p.max_frames_between_keyframes >= 0, "max_frames_between_keyframes",
          "must be >= 0 (0: the camera's fps)");
  p.min_frames_between_keyframes = r.get("min_frames_between_keyframes", p.min_frames_between_keyframes);
  r.check(p.min_frames_between_keyframes >= 0, "min_frames_between_keyframes", "must be >= 0");
  p.reference_ratio = r.get("reference_ratio", p.reference_ratio);
  r.check(p.reference_ratio > 0 && p.reference_ratio <= 1, "reference_ratio", "must be in (0, 1]");
  p.keyframe_close_points = r.get("keyframe_close_points", p.keyframe_close_points);
  r.check(p.keyframe_close_points >= 0, "keyframe_close_points", "must be >= 0");
  p.keyframe_close_tracked = r.get("keyframe_close_tracked", p.keyframe_close_tracked);
  r.check(p.keyframe_close_tracked >= 0, "keyframe_close_tracked", "must be >= 0");
  p.keyframe_close_untracked = r.get("keyframe_close_untracked", p.keyframe_close_untracked);
  r.check(p.keyframe_close_untracked >= 0, "keyframe_close_untracked", "must be >= 0");
  p.keyframe_coverage = r.get("keyframe_coverage", p.keyframe_coverage);
  r.check(p.keyframe_coverage >= 0 && p.keyframe_coverage <= 1, "keyframe_coverage", "must be in [0, 1]");
  p.discount_hidden_points = r.get("discount_hidden_points", p.discount_hidden_points);
  p.min_relocalization_inliers = r.get("min_relocalization_inliers", p.min_relocalization_inliers);
  r.check(p.min_relocalization_inliers >= 6, "min_relocalization_inliers", "must be >= 6");
  p.max_camera_speed = r.get("max_camera_speed", p.max_camera_speed);
  r.check(p.max_camera_speed >= 0 && p.max_camera_speed <= 1000, "max_camera_speed",
          "must be in [0, 1000] (0: no limit)");
  r.finish();
  return p;
}

Tracker::Tracker(map::Map& map, mapping::LocalMapper& mapper, TrackerParams params)
    : map_(map),
      mapper_(mapper),
      params_(params),
      keyframes_(map, mapper, params_),
      motion_matcher_({0.9f, true}),
      reference_matcher_({0.7f, true}),
      local_matcher_({0.8f, false}),
      reclamation_(map.reclamation(), "tracking") {}

TrackOutcome Tracker::track(data::Frame& frame) {
  TrackOutcome outcome;
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_lock lock(map_.mutex());
  outcome.wait_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  if (state_ == TrackingState::NotInitialized) {
    outcome.new_keyframe = initialize(frame);
  } else {
    const bool ok = track_frame(frame, outcome);
    state_ = ok ? TrackingState::Ok : TrackingState::Lost;
    if (ok) {
      // The first frame placed in a loaded map has no last frame to measure a velocity from.
      if (last_frame_ && !restarted_motion_)
        update_velocity(frame);
      else
        velocity_.reset();
      const KeyFrameContext context{reference_kf_, inliers_,
                                    recovered_ ? std::optional(recovered_frame_id_) : std::nullopt};
      if (!localization_only_ && keyframes_.needed(frame, context)) {
        outcome.new_keyframe = keyframes_.insert(frame);
        reference_kf_ = outcome.new_keyframe;
      }
      // Outliers do not carry over to the next frame's motion model.
      for (std::size_t i = 0; i < frame.size(); ++i)
        if (frame.outliers[i]) frame.map_points[i] = nullptr;
    } else {
      velocity_.reset();
      // Until a frame is placed in a loaded map, the state says so (it is not a loss of track).
      if (!last_frame_) state_ = TrackingState::NotLocalized;
    }
  }
  record(frame);
  let_go_of_removed_objects();
  if (outcome.new_keyframe != nullptr) {
    outcome.new_keyframe_id = outcome.new_keyframe->id();
    outcome.new_keyframe_T_wc = outcome.new_keyframe->T_wc();
    outcome.new_keyframe_points = static_cast<std::size_t>(outcome.new_keyframe->tracked_map_points(1));
  }
  outcome.state = state_;
  outcome.inliers = inliers_;
  if (state_ == TrackingState::Ok && frame.has_pose()) {
    outcome.T_cw = frame.T_cw();
    outcome.local_keyframes = local_keyframes_.size();
    outcome.local_points = local_points_.size();
  }
  return outcome;
}

bool Tracker::track_frame(data::Frame& frame, TrackOutcome& outcome) {
  // Points replaced by fusion since the last frame.
  if (last_frame_)
    for (auto& mp : last_frame_->map_points)
      while (mp != nullptr && mp->replaced_by() != nullptr) mp = mp->replaced_by();
  update_last_frame();
  ++search_pass_;
  restarted_motion_ = false;
  bool ok = false;
  if (state_ == TrackingState::NotLocalized) {
    // A loaded map and no frame placed in it yet: no last pose to fall back on, only place
    // recognition can place the frame (issue 20).
    ok = outcome.relocalized = relocalize(frame);
    if (ok) {
      recovered_ = true;
      recovered_frame_id_ = frame.id();
    }
  } else if (state_ == TrackingState::Ok) {
    // Keypoints to the stamp before any matching (a global shutter: nothing moves).
    if (velocity_)
      compensate_rolling_shutter(frame, *velocity_,
                                 frame_period_ > 0.0 ? frame_period_ : 1.0 / frame.camera().fps);
    if (velocity_ && !recently_recovered(frame)) ok = track_with_motion_model(frame);
    if (!ok) ok = track_reference_keyframe(frame);
  } else {
    ok = recover(frame, outcome);
    if (ok) {
      recovered_ = true;
      recovered_frame_id_ = frame.id();
      velocity_.reset();
    }
  }
  if (ok && moving_point_check_ != nullptr) {
    std::vector<map::KeyFrame*> nearby = local_keyframes_;
    if (reference_kf_ != nullptr && std::find(nearby.begin(), nearby.end(), reference_kf_) == nearby.end())
      nearby.push_back(reference_kf_);
    outcome.geometry = moving_point_check_->remove_moving_points(frame, nearby);
  }
  if (ok) ok = track_local_map(frame);
  if (ok) check_camera_speed(frame);
  outcome.relocalized = outcome.relocalized && ok;
  if (outcome.relocalized) {
    ++relocalizations_;
    replace_frames_followed_before_loss(frame);
  }
  return ok;
}

void Tracker::record(const data::Frame& frame) {
  FrameRecord rec;
  rec.frame_id = frame.id();
  rec.timestamp = frame.timestamp();
  rec.state = state_;
  rec.inliers = inliers_;
  const std::optional<std::uint64_t> previous = std::exchange(previous_reference_, std::nullopt);
  if (state_ == TrackingState::Ok && frame.has_pose() && reference_kf_ != nullptr) {
    rec.reference = reference_kf_->id();
    previous_reference_ = rec.reference;
    if (!restarted_motion_) link_references(previous, reference_kf_);
    rec.T_c_ref = frame.T_cw() * reference_kf_->T_wc();
    last_frame_reference_ = reference_kf_->id();
    last_T_c_ref_ = rec.T_c_ref;
    // The live pose, as a robot sees it (the trajectory files hold the final ones), and the step
    // from the last frame as its keyframe stands now (a loop correction moved both): tells a jump
    // made by tracking from one made by corrections of the keyframes.
    if (spdlog::should_log(spdlog::level::debug)) log_live_pose(frame);
  }
  records_.push_back(rec);
  if (state_ == TrackingState::Ok)
    last_frame_ = frame;
  else if (last_frame_)
    last_frame_->map_points.assign(last_frame_->size(), nullptr);
}

std::optional<Eigen::Isometry3d> Tracker::predicted_pose(double timestamp) const {
  if (state_ != TrackingState::Ok || !last_frame_ || !last_frame_->has_pose()) return std::nullopt;
  if (!velocity_) return last_frame_->T_cw();
  return motion_model_pose(timestamp);
}

int Tracker::frame_steps(double timestamp) const {
  // Beyond a third of a second at 30 Hz the constant velocity is a guess either way; the
  // reference keyframe and relocalization take over when it fails.
  constexpr long kMaxSteps = 10;
  const double dt = timestamp - last_frame_->timestamp();
  if (frame_period_ <= 0.0 || !(dt > 0.0)) return 1;
  return static_cast<int>(std::clamp(std::lround(dt / frame_period_), 1L, kMaxSteps));
}

Eigen::Isometry3d Tracker::motion_model_pose(double timestamp) const {
  // The camera keeps its velocity over every frame since the last tracked one, dropped ones too.
  const int steps = frame_steps(timestamp);
  if (steps == 1) return *velocity_ * last_frame_->T_cw();
  Eigen::Isometry3d T_cw = last_frame_->T_cw();
  for (int step = 0; step < steps; ++step) T_cw = *velocity_ * T_cw;
  return geometry::orthonormalized(T_cw);
}

void Tracker::update_velocity(const data::Frame& frame) {
  // The motion per camera frame: one n-th of the motion since the last tracked frame when n-1
  // frames between were dropped. Stamp jitter rounds away, so a sequence without gaps gives the
  // plain frame-to-frame velocity.
  const int steps = frame_steps(frame.timestamp());
  const Eigen::Isometry3d motion = frame.T_cw() * last_frame_->T_wc();
  velocity_ = steps == 1 ? motion : geometry::orthonormalized(geometry::se3_power(motion, 1.0 / steps));
  const double dt = frame.timestamp() - last_frame_->timestamp();
  if (steps == 1 && dt > 0.0) frame_period_ = dt;
}

bool Tracker::recently_recovered(const data::Frame& frame) const {
  return recovered_ && frame.id() < recovered_frame_id_ + 2;
}

map::KeyFrame* Tracker::initialize(data::Frame& frame) {
  std::size_t with_depth = 0;
  for (std::size_t i = 0; i < frame.size(); ++i) with_depth += frame.depth(i) > 0.0f ? 1 : 0;
  if (with_depth < static_cast<std::size_t>(params_.init_min_features)) return nullptr;

  // The first keyframe defines the world frame.
  frame.set_pose(Eigen::Isometry3d::Identity());
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  std::fill(frame.outliers.begin(), frame.outliers.end(), false);
  map::KeyFrame* kf = map_.create_keyframe(frame);
  for (std::size_t i = 0; i < frame.size(); ++i) add_point_from_depth(map_, kf, frame, i);
  mapper_.insert_keyframe(kf);
  keyframes_.inserted_first(frame);
  reference_kf_ = kf;
  local_keyframes_ = {kf};
  local_points_ = map_.map_points();
  inliers_ = static_cast<int>(with_depth);
  state_ = TrackingState::Ok;
  return kf;
}

void Tracker::log_live_pose(const data::Frame& frame) const {
  const Eigen::Vector3d t_wc = frame.T_wc().translation();
  const double step =
      last_frame_ && last_frame_->has_pose() ? (t_wc - last_frame_->T_wc().translation()).norm() : 0.0;
  spdlog::debug(
      "frame {}: tracked at ({:.3f}, {:.3f}, {:.3f}), {:.3f} m from the last frame, reference keyframe {}",
      frame.id(), t_wc.x(), t_wc.y(), t_wc.z(), step, reference_kf_->id());
}

void Tracker::link_references(std::optional<std::uint64_t> previous, map::KeyFrame* current) {
  // The trajectory passes from the last frame's reference keyframe to this one's here: loop
  // closing and global BA must not tear the two apart (optim/odometry_change.h). A frame
  // relocalized after a lost one starts anew and links nothing.
  if (!previous || *previous == current->id()) return;
  map::KeyFrame* before = map_.keyframe(*previous);
  if (before == nullptr || before->is_bad()) return;
  before->add_tracking_link(current);
}

void Tracker::update_last_frame() {
  // The last frame's pose from its reference keyframe, which local BA may have moved.
  if (!last_frame_reference_) return;
  if (const map::KeyFrame* ref = map_.keyframe(*last_frame_reference_))
    last_frame_->set_pose(last_T_c_ref_ * ref->T_cw());
}

void Tracker::let_go_of_removed_objects() {
  // After a tracked frame everything here was found in the map during this hold; after a lost
  // one the local map and the reference keyframe may be old.
  if (last_frame_)
    for (auto& mp : last_frame_->map_points) {
      while (mp != nullptr && mp->replaced_by() != nullptr) mp = mp->replaced_by();
      if (mp != nullptr && mp->is_bad()) mp = nullptr;
    }
  std::erase_if(local_keyframes_, [](const map::KeyFrame* kf) { return kf->is_bad(); });
  std::erase_if(local_points_, [](const map::MapPoint* mp) { return mp->is_bad(); });
  if (reference_kf_ != nullptr && reference_kf_->is_bad())
    reference_kf_ = map_.nearest_active_keyframe(reference_kf_->id());
  reclamation_.quiescent();
}

int Tracker::optimize_pose(data::Frame& frame) {
  const auto result = optim::optimize_frame_pose(frame, frame.map_points, frame.T_cw(), params_.pose);
  if (result.outlier.empty()) return 0;
  frame.set_pose(result.T_cw);
  for (std::size_t i = 0; i < frame.size(); ++i)
    if (frame.map_points[i] != nullptr) frame.outliers[i] = result.outlier[i];
  return result.inliers;
}

bool Tracker::track_reference_keyframe(data::Frame& frame) {
  if (reference_kf_ == nullptr || reference_kf_->is_bad()) {
    std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
    std::fill(frame.outliers.begin(), frame.outliers.end(), false);
    return false;
  }
  return track_keyframe(frame, *reference_kf_, last_frame_->T_cw());
}

bool Tracker::track_keyframe(data::Frame& frame, const map::KeyFrame& kf, const Eigen::Isometry3d& T_cw) {
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  std::fill(frame.outliers.begin(), frame.outliers.end(), false);
  const int matches = reference_matcher_.search_by_descriptor(kf, frame);
  spdlog::debug("frame {}: reference keyframe {} matches {}", frame.id(), kf.id(), matches);
  if (matches < params_.min_reference_matches) return false;
  frame.set_pose(T_cw);
  optimize_pose(frame);
  return discard_outliers(frame, search_pass_) >= params_.min_pose_inliers;
}

bool Tracker::track_with_motion_model(data::Frame& frame) {
  frame.set_pose(motion_model_pose(frame.timestamp()));
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  std::fill(frame.outliers.begin(), frame.outliers.end(), false);
  int matches = motion_matcher_.search_by_projection(frame, *last_frame_, params_.motion_model_radius);
  if (matches < params_.min_motion_matches) {
    std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
    matches = motion_matcher_.search_by_projection(frame, *last_frame_, 2.0f * params_.motion_model_radius);
  }
  spdlog::debug("frame {}: motion model {} matches", frame.id(), matches);
  if (matches < params_.min_motion_matches) return false;
  optimize_pose(frame);
  return discard_outliers(frame, search_pass_) >= params_.min_pose_inliers;
}

bool Tracker::track_local_map(data::Frame& frame) {
  update_local_keyframes(frame);
  update_local_points();
  const int found = search_local_points(frame);
  optimize_pose(frame);
  inliers_ = 0;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    map::MapPoint* mp = frame.map_points[i];
    if (mp == nullptr || frame.outliers[i]) continue;
    mp->increase_found();
    if (mp->num_observations() > 0) ++inliers_;
  }
  spdlog::debug("frame {}: local map {} kfs {} points, {} found, {} inliers", frame.id(),
                local_keyframes_.size(), local_points_.size(), found, inliers_);
  if (recently_recovered(frame) && inliers_ < params_.min_inliers_after_recovery) return false;
  return inliers_ >= params_.min_local_map_inliers;
}

void Tracker::update_local_keyframes(data::Frame& frame) {
  // Keyframes sharing points with the frame, by number of shared points: counted on the keyframes
  // themselves rather than in a map rebuilt every frame, then taken in id order.
  const std::uint64_t count_tag = ++sharing_count_pass_;
  std::vector<map::KeyFrame*>& sharing = sharing_keyframes_;  // scratch: no allocation per frame
  sharing.clear();
  for (std::size_t i = 0; i < frame.size(); ++i) {
    map::MapPoint* mp = frame.map_points[i];
    if (mp == nullptr) continue;
    if (mp->is_bad()) {
      frame.map_points[i] = nullptr;
      continue;
    }
    for (const auto& [kf, idx] : mp->observations()) {
      if (kf->track_count_for_frame != count_tag) {
        kf->track_count_for_frame = count_tag;
        kf->track_shared_points = 0;
        sharing.push_back(kf);
      }
      ++kf->track_shared_points;
    }
  }
  if (sharing.empty()) return;
  std::sort(sharing.begin(), sharing.end(), map::ById{});
  std::erase_if(sharing, [](const map::KeyFrame* kf) { return kf->is_bad(); });
  const std::uint64_t tag = search_pass_;
  const auto max_kfs = static_cast<std::size_t>(params_.max_local_keyframes);
  // At most max_local_keyframes of them, those sharing the most (issue 23: where laps pile up
  // keyframes over the same room, every one sharing a few points would enter, and tracking's cost
  // would grow with the time spent there); kept in id order, as below the cap.
  if (sharing.size() > max_kfs) {
    std::stable_sort(sharing.begin(), sharing.end(), [](const map::KeyFrame* a, const map::KeyFrame* b) {
      return a->track_shared_points > b->track_shared_points;
    });
    sharing.resize(max_kfs);
    std::sort(sharing.begin(), sharing.end(), map::ById{});
  }
  local_keyframes_.clear();
  map::KeyFrame* best = nullptr;
  int best_count = 0;
  for (map::KeyFrame* kf : sharing) {
    if (kf->track_shared_points > best_count) {
      best_count = kf->track_shared_points;
      best = kf;
    }
    local_keyframes_.push_back(kf);
    kf->track_reference_for_frame = tag;
  }
  // Plus some neighbours of those: best covisibles, a child and the parent.
  const std::size_t first_order = local_keyframes_.size();
  auto try_add = [&](map::KeyFrame* kf) {
    if (kf == nullptr || kf->is_bad() || kf->track_reference_for_frame == tag) return false;
    kf->track_reference_for_frame = tag;
    local_keyframes_.push_back(kf);
    return true;
  };
  for (std::size_t i = 0; i < first_order && local_keyframes_.size() < max_kfs; ++i) {
    map::KeyFrame* kf = local_keyframes_[i];
    for (map::KeyFrame* n : kf->best_covisibles(10))
      if (try_add(n)) break;
    for (map::KeyFrame* c : kf->children())
      if (try_add(c)) break;
    try_add(kf->parent());
  }
  if (best != nullptr) reference_kf_ = best;
}

void Tracker::update_local_points() {
  local_points_.clear();
  const std::uint64_t tag = search_pass_;
  for (map::KeyFrame* kf : local_keyframes_) {
    for (map::MapPoint* mp : kf->map_points()) {
      if (mp == nullptr || mp->is_bad() || mp->track.local_for_frame == tag) continue;
      mp->track.local_for_frame = tag;
      local_points_.push_back(mp);
    }
  }
}

int Tracker::search_local_points(data::Frame& frame) {
  const std::uint64_t tag = search_pass_;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    map::MapPoint* mp = frame.map_points[i];
    if (mp == nullptr) continue;
    if (mp->is_bad()) {
      frame.map_points[i] = nullptr;
      continue;
    }
    mp->increase_visible();
    mp->track.last_frame_seen = tag;
    mp->track.in_view = false;
  }
  int to_match = 0;
  for (map::MapPoint* mp : local_points_) {
    if (mp->track.last_frame_seen == tag || mp->is_bad()) {
      if (mp->track.last_frame_seen != tag) mp->track.in_view = false;
      continue;
    }
    if (!match::mark_for_projection_search(frame, *mp)) continue;
    mp->increase_visible();
    ++to_match;
  }
  if (to_match == 0) return 0;
  const float th = recently_recovered(frame) ? 5.0f : params_.local_map_radius;
  return local_matcher_.search_by_projection(frame, local_points_, th);
}

}  // namespace lrd::tracking
