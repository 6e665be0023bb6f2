#include "lrd/tracking/tracker.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <mutex>

#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/map/map_point.h"
#include "lrd/mapping/local_mapper.h"
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

Tracker::Tracker(map::Map& map, mapping::LocalMapper& mapper, TrackerParams params)
    : map_(map),
      mapper_(mapper),
      params_(params),
      keyframes_(map, mapper, params_),
      motion_matcher_({0.9f, true}),
      reference_matcher_({0.7f, true}),
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
        motion_.update(frame.T_cw(), frame.timestamp(), last_frame_->T_cw(), last_frame_->timestamp());
      else
        motion_.reset();
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
      motion_.reset();
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
    outcome.local_keyframes = local_map_.keyframes().size();
    outcome.local_points = local_map_.points().size();
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
    // recognition can place the frame (docs/map-files.md).
    ok = outcome.relocalized = relocalize(frame);
    if (ok) {
      recovered_ = true;
      recovered_frame_id_ = frame.id();
    }
  } else if (state_ == TrackingState::Ok) {
    // Keypoints to the stamp before any matching (a global shutter: nothing moves).
    if (motion_.has_velocity())
      compensate_rolling_shutter(frame, motion_.velocity(), motion_.frame_period(frame.camera().fps));
    if (motion_.has_velocity() && !recently_recovered(frame)) ok = track_with_motion_model(frame);
    if (!ok) ok = track_reference_keyframe(frame);
  } else {
    ok = recover(frame, outcome);
    if (ok) {
      recovered_ = true;
      recovered_frame_id_ = frame.id();
      motion_.reset();
    }
  }
  if (ok && moving_point_check_ != nullptr) {
    std::vector<map::KeyFrame*> nearby = local_map_.keyframes();
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

std::optional<Eigen::Isometry3d> Tracker::predicted_pose(double timestamp) const {
  if (state_ != TrackingState::Ok || !last_frame_ || !last_frame_->has_pose()) return std::nullopt;
  if (!motion_.has_velocity()) return last_frame_->T_cw();
  return motion_model_pose(timestamp);
}

Eigen::Isometry3d Tracker::motion_model_pose(double timestamp) const {
  return motion_.predict(last_frame_->T_cw(), last_frame_->timestamp(), timestamp);
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
  local_map_.start(kf, map_.map_points());
  inliers_ = static_cast<int>(with_depth);
  state_ = TrackingState::Ok;
  return kf;
}

void Tracker::let_go_of_removed_objects() {
  // After a tracked frame everything here was found in the map during this hold; after a lost
  // one the local map and the reference keyframe may be old.
  if (last_frame_)
    for (auto& mp : last_frame_->map_points) {
      while (mp != nullptr && mp->replaced_by() != nullptr) mp = mp->replaced_by();
      if (mp != nullptr && mp->is_bad()) mp = nullptr;
    }
  local_map_.drop_removed();
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
  const auto max_keyframes = static_cast<std::size_t>(params_.max_local_keyframes);
  if (map::KeyFrame* best = local_map_.update(frame, search_pass_, max_keyframes)) reference_kf_ = best;
  const float radius = recently_recovered(frame) ? 5.0f : params_.local_map_radius;
  const int found = local_map_.search(frame, search_pass_, radius);
  optimize_pose(frame);
  inliers_ = 0;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    map::MapPoint* mp = frame.map_points[i];
    if (mp == nullptr || frame.outliers[i]) continue;
    mp->increase_found();
    if (mp->num_observations() > 0) ++inliers_;
  }
  spdlog::debug("frame {}: local map {} kfs {} points, {} found, {} inliers", frame.id(),
                local_map_.keyframes().size(), local_map_.points().size(), found, inliers_);
  if (recently_recovered(frame) && inliers_ < params_.min_inliers_after_recovery) return false;
  return inliers_ >= params_.min_local_map_inliers;
}

}  // namespace lrd::tracking
