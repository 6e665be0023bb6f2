// The Tracker's record of each frame (tracker.h): its pose relative to its reference keyframe, so
// the trajectory follows later corrections of the map, and the tracking links between reference
// keyframes that loop closing keeps together.
#include <spdlog/spdlog.h>

#include <utility>

#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/tracking/tracker.h"

namespace lrd::tracking {

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

}  // namespace lrd::tracking
