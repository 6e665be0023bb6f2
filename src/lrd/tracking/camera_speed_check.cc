// Tracking against the camera's speed limit, tracking.max_camera_speed (docs/slam-core.md, "Moving
// faster than a camera"; the divergence runs in bench/results/log/divergence.md):
//  - Tracker::check_camera_speed: tracking that moved the camera faster than the limit followed a
//    person walking past; the frame is tracked again from where that stride began, and the frames
//    that followed are placed again; those it cannot track again are placed again when a
//    relocalization soon after finds the map. Tracking that comes back to the map in one step
//    beyond the limit places the frames of the way out again.
//  - Tracker::recover: after a brief loss, a relocalization beyond where the camera can have gone
//    gives way to tracking from the last pose, and suggests the loop that merges the two copies
//    of the place it found.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>
#include <string>
#include <utility>

#include "lrd/geometry/se3.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/tracking/camera_stride.h"
#include "lrd/tracking/tracker.h"

namespace lrd::tracking {
namespace {
// Six frames at 30 Hz: long enough to average jitter out; at least three (stamps are rounded).
constexpr double kWindowSeconds = 0.2, kMinSeconds = 0.09;
// A relocalization this soon after the last frame over the limit places the frames that followed
// (run 17 of walking_rpy static came back 0.1 s after).
constexpr double kFollowedLossSeconds = 0.5;
// Lost for longer than this, the camera may be anywhere: a relocalization is taken wherever it is.
constexpr double kBriefLossSeconds = 1.0;
// A step beyond the limit comes back when it turns more than 120 degrees from the way out.
constexpr double kReturnCosine = 0.5;
}  // namespace

bool Tracker::recover(data::Frame& frame, TrackOutcome& outcome) {
  // Relocalize by place recognition; failing that (or without a vocabulary), try the last
  // reference keyframe from the last known pose.
  map::KeyFrame* const last_reference = reference_kf_;
  if (!relocalize(frame)) return track_reference_keyframe(frame);
  const std::optional<double> metres = implausible_recovery(frame);
  if (!metres) return outcome.relocalized = true;
  suggest_crossing(frame, *reference_kf_);
  // No candidate placed the camera where it can have gone since it was lost: the map holds this
  // place twice, apart by its drift (a static-mode walking_rpy run relocalized 1.15 m from where it
  // was lost a frame before; bench/results/log/divergence.md). Tracked from the last pose instead,
  // the trajectory does not jump; failing that the frame stays lost, and after a second lost any
  // relocalization stands.
  data::Frame near = frame;
  map::KeyFrame* const relocalized_kf = reference_kf_;
  reference_kf_ = last_reference;
  if (track_reference_keyframe(near)) {
    spdlog::info(
        "frame {}: relocalized against keyframe {} {:.2f} m from the last tracked pose, beyond the "
        "speed limit: tracked from the last pose against keyframe {} instead",
        frame.id(), relocalized_kf->id(), *metres, last_reference->id());
    frame = std::move(near);
    return true;
  }
  spdlog::info(
      "frame {}: relocalized against keyframe {} {:.2f} m from the last tracked pose, beyond the "
      "speed limit, and not tracked from the last pose: lost",
      frame.id(), relocalized_kf->id(), *metres);
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  return false;
}

const FrameRecord* Tracker::last_tracked_record() const {
  const auto last = std::find_if(records_.rbegin(), records_.rend(), [](const FrameRecord& r) {
    return r.state == TrackingState::Ok && r.reference.has_value();
  });
  return last == records_.rend() ? nullptr : &*last;
}

void Tracker::suggest_crossing(const data::Frame& frame, const map::KeyFrame& found) const {
  // Relocalized beyond where the camera can have gone, tracking found the place it left held a
  // second time by the map: the loop between the two copies, closed, moves the frames tracked
  // before the loss with their keyframes instead of leaving a step in the trajectory (walking_xyz
  // static: 1.03 m; bench/results/log/divergence.md). The camera barely moved in the frames it was
  // lost: where the relocalization puts it now is where it was last tracked, relative to the
  // keyframe it was tracked against. The loop closer verifies it.
  if (!crossing_callback_ || localization_only_) return;
  const FrameRecord* last = last_tracked_record();
  const map::KeyFrame* lost = last != nullptr ? map_.keyframe(*last->reference) : nullptr;
  if (lost == nullptr || lost->is_bad() || lost == &found) return;
  spdlog::debug("frame {}: suggests a loop between keyframes {} and {}", frame.id(), lost->id(), found.id());
  crossing_callback_({lost->id(), found.id(), last->T_c_ref.inverse() * frame.T_cw()});
}

std::optional<double> Tracker::implausible_recovery(const data::Frame& frame) const {
  if (params_.max_camera_speed <= 0.0) return std::nullopt;
  const FrameRecord* last = last_tracked_record();
  if (last == nullptr || frame.timestamp() - last->timestamp > kBriefLossSeconds) return std::nullopt;
  const std::optional<double> metres = beyond_speed_limit(*last, frame);
  // Frames over the limit just before may have followed a person away from the camera: where the
  // first of them began its stride counts too (replace_frames_followed_before_loss).
  if (metres && followed_since_ && frame.timestamp() - followed_until_ <= kFollowedLossSeconds &&
      !beyond_speed_limit(*followed_since_, frame))
    return std::nullopt;
  return metres;
}

std::optional<double> Tracker::beyond_speed_limit(const FrameRecord& from, const data::Frame& frame) const {
  const double metres = (frame.T_wc().translation() - recorded_centre(from, map_)).norm();
  if (metres <= params_.max_camera_speed * (frame.timestamp() - from.timestamp)) return std::nullopt;
  return metres;
}

void Tracker::check_camera_speed(data::Frame& frame) {
  if (params_.max_camera_speed <= 0.0) return;
  if (replace_frames_before_a_return(frame)) return;
  const auto stride = recent_stride(records_, map_, frame.timestamp(), frame.T_wc().translation(),
                                    kWindowSeconds, kMinSeconds);
  if (!stride) return;
  if (stride->speed() <= params_.max_camera_speed) {
    followed_since_.reset();
    return;
  }
  ++implausible_motions_;
  const std::string what = fmt::format(
      "frame {}: tracking moved the camera {:.2f} m in {:.2f} s ({:.1f} m/s, over tracking.max_camera_speed "
      "{:.2f});",
      frame.id(), stride->metres, stride->seconds, stride->speed(), params_.max_camera_speed);
  // Where the stride began the camera was still on the map, and a camera keeping to its speed
  // limit is near there: tracked again from that pose, the frame finds the map that stood still.
  // Otherwise the first result stands: losing the frame would hand it to relocalization, which
  // jumps by all the drift at once where tracking would have worked it off (walking_xyz static:
  // 0.8-1.3 m jumps; bench/results/divergence.md).
  const FrameRecord from = *stride->from;
  SearchState first{reference_kf_, local_map_.contents(), inliers_};
  data::Frame again = frame;
  if (track_again_from(again, from)) {
    const double metres = (again.T_wc().translation() - stride->from_t_wc).norm();
    if (metres <= params_.max_camera_speed * (again.timestamp() - from.timestamp)) {
      spdlog::info(
          "{} it followed something that moves: tracked again from frame {}'s pose, {:.2f} m from it", what,
          from.frame_id, metres);
      frame = std::move(again);
      if (followed_since_) followed_until_ = frame.timestamp();  // tracked again from a followed pose
      restarted_motion_ = true;  // no velocity and no tracking link from the frames that followed
      replace_followed_frames(from, frame);
      return;
    }
    spdlog::info("{} tracked again from frame {}'s pose it is {:.2f} m from there: kept", what, from.frame_id,
                 metres);
  } else {
    spdlog::info("{} not tracked again from frame {}'s pose: kept", what, from.frame_id);
  }
  if (!followed_since_) followed_since_ = from;
  followed_until_ = frame.timestamp();
  reference_kf_ = first.reference;
  local_map_.restore(std::move(first.local_map));
  inliers_ = first.inliers;
}

bool Tracker::replace_frames_before_a_return(const data::Frame& frame) {
  // Tracking can follow a person at just under the limit and come back to the map that stood still
  // in one frame (walking_xyz static: frames 795-799 5 cm a frame, then 0.52 m back at frame 800,
  // 1 cm in truth; bench/results/log/divergence.md): a stride measured over 0.2 s hides a way out
  // and back. A step from the last tracked frame beyond the limit, turning back towards an earlier
  // frame and landing within the limit of it (within a second), with more inliers than the last
  // frame (the map agrees more: back on what stood still, not onto another person), means the
  // frames between went out and came back faster than a camera can: they are placed again on the
  // path from that frame to this one.
  const FrameRecord* last = last_tracked_record();
  if (last == nullptr || inliers_ <= last->inliers) return false;
  const std::optional<double> step = beyond_speed_limit(*last, frame);
  if (!step) return false;
  std::optional<FrameRecord> from = return_anchor(frame, *last);
  if (!from) return false;
  ++implausible_motions_;
  spdlog::info(
      "frame {}: tracking came back {:.2f} m from frame {} ({} inliers, {} there), within the speed limit "
      "of frame {}: the frames between followed something that moves, placed again on the path",
      frame.id(), *step, last->frame_id, inliers_, last->inliers, from->frame_id);
  replace_followed_frames(*from, frame);
  restarted_motion_ = true;
  followed_since_.reset();
  return true;
}

std::optional<FrameRecord> Tracker::return_anchor(const data::Frame& frame, const FrameRecord& last) const {
  // Where frames over the limit began to follow, when the camera can have gone from there.
  if (followed_since_ && !beyond_speed_limit(*followed_since_, frame)) return followed_since_;
  // Else the latest frame before `last` it can have come from, the step turning back towards it:
  // a camera truly moving faster than its limit keeps its direction.
  const Eigen::Vector3d at_last = recorded_centre(last, map_);
  for (auto it = records_.rbegin(); it != records_.rend(); ++it) {
    if (frame.timestamp() - it->timestamp > kBriefLossSeconds) return std::nullopt;
    if (it->frame_id >= last.frame_id || it->state != TrackingState::Ok || !it->reference) continue;
    if (beyond_speed_limit(*it, frame)) continue;
    const Eigen::Vector3d out = at_last - recorded_centre(*it, map_),
                          back = frame.T_wc().translation() - at_last;
    if (out.dot(back) > -kReturnCosine * out.norm() * back.norm()) return std::nullopt;
    return *it;
  }
  return std::nullopt;
}

void Tracker::replace_followed_frames(const FrameRecord& from, const data::Frame& found) {
  // The frames since `from` followed something else: their poses are placed again on the path
  // between the two the map agrees with, by their stamps (the camera kept within its speed limit
  // meanwhile), relative to from's reference keyframe. The trajectory files then hold no step
  // where tracking came back; the live poses published for those frames stay as they were.
  const Eigen::Isometry3d T_w_from = map_.resolve_pose(*from.reference, from.T_c_ref).inverse();
  const Eigen::Isometry3d T_w_ref = map_.resolve_pose(*from.reference).inverse();
  const Eigen::Isometry3d stride = T_w_from.inverse() * found.T_wc();
  const double seconds = found.timestamp() - from.timestamp;
  for (auto it = records_.rbegin(); it != records_.rend() && it->frame_id != from.frame_id; ++it) {
    if (it->state != TrackingState::Ok) continue;  // a lost frame stays lost
    const Eigen::Isometry3d T_wc =
        T_w_from * geometry::se3_power(stride, (it->timestamp - from.timestamp) / seconds);
    it->reference = from.reference;
    it->T_c_ref = T_wc.inverse() * T_w_ref;
  }
}

void Tracker::replace_frames_followed_before_loss(const data::Frame& relocalized) {
  // Tracking that followed a person until the map no longer agreed is lost, then relocalized
  // against the map that stood still: without this, the trajectory steps back by all it followed
  // at once (walking_rpy static, run 17: 0.84 m; bench/results/log/divergence.md).
  if (!followed_since_) return;
  const FrameRecord from = *std::exchange(followed_since_, std::nullopt);
  const double lost_seconds = relocalized.timestamp() - followed_until_;
  if (lost_seconds > kFollowedLossSeconds) return;  // lost for longer: too far back to judge
  if (const auto metres = beyond_speed_limit(from, relocalized)) {
    spdlog::info(
        "frame {}: relocalized {:.2f} m from frame {}'s pose in {:.2f} s, over the speed limit: "
        "the frames between keep their poses",
        relocalized.id(), *metres, from.frame_id, relocalized.timestamp() - from.timestamp);
    return;
  }
  spdlog::info(
      "frame {}: relocalized within the speed limit of frame {}'s pose, {:.2f} s after the last frame it "
      "flagged as too fast: the frames between placed again on the path",
      relocalized.id(), from.frame_id, lost_seconds);
  replace_followed_frames(from, relocalized);
}

bool Tracker::track_again_from(data::Frame& frame, const FrameRecord& from) {
  map::KeyFrame* kf = map_.nearest_active_keyframe(*from.reference);
  if (kf == nullptr) return false;
  ++search_pass_;
  if (!track_keyframe(frame, *kf, map_.resolve_pose(*from.reference, from.T_c_ref))) return false;
  reference_kf_ = kf;
  return track_local_map(frame);
}

}  // namespace lrd::tracking
