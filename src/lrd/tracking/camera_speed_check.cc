// Tracker::check_camera_speed (reliability issue 22): tracking that moved the camera faster than
// tracking.max_camera_speed followed a person walking past; the frame is tracked again from where
// that stride began, and the frames that followed are placed again (docs/slam-core.md, "Moving
// faster than a camera").
#include <spdlog/spdlog.h>

#include <string>
#include <utility>

#include "lrd/geometry/se3.h"
#include "lrd/map/map.h"
#include "lrd/tracking/camera_stride.h"
#include "lrd/tracking/tracker.h"

namespace lrd::tracking {

void Tracker::check_camera_speed(data::Frame& frame) {
  // Six frames at 30 Hz: long enough to average jitter out; at least three (stamps are rounded).
  constexpr double kWindowSeconds = 0.2, kMinSeconds = 0.09;
  if (params_.max_camera_speed <= 0.0) return;
  const auto stride = recent_stride(records_, map_, frame.timestamp(), frame.T_wc().translation(),
                                    kWindowSeconds, kMinSeconds);
  if (!stride || stride->speed() <= params_.max_camera_speed) return;
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
  SearchState first{reference_kf_, local_keyframes_, local_points_, inliers_};
  data::Frame again = frame;
  if (track_again_from(again, from)) {
    const double metres = (again.T_wc().translation() - stride->from_t_wc).norm();
    if (metres <= params_.max_camera_speed * (again.timestamp() - from.timestamp)) {
      spdlog::info(
          "{} it followed something that moves: tracked again from frame {}'s pose, {:.2f} m from it", what,
          from.frame_id, metres);
      frame = std::move(again);
      restarted_motion_ = true;  // no velocity and no tracking link from the frames that followed
      replace_followed_frames(from, frame);
      return;
    }
    spdlog::info("{} tracked again from frame {}'s pose it is {:.2f} m from there: kept", what, from.frame_id,
                 metres);
  } else {
    spdlog::info("{} not tracked again from frame {}'s pose: kept", what, from.frame_id);
  }
  reference_kf_ = first.reference;
  local_keyframes_ = std::move(first.local_keyframes);
  local_points_ = std::move(first.local_points);
  inliers_ = first.inliers;
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
    const Eigen::Isometry3d T_wc =
        T_w_from * geometry::se3_power(stride, (it->timestamp - from.timestamp) / seconds);
    it->reference = from.reference;
    it->T_c_ref = T_wc.inverse() * T_w_ref;
  }
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
