#pragma once
// The constant-velocity motion model (ORB-SLAM2's, paper §2.2): the camera keeps the velocity it
// had between the last two tracked frames, over every camera frame since the last tracked one
// (dropped frames too). Also the camera's frame period, as the stamps show it.
#include <Eigen/Geometry>
#include <optional>

namespace lrd::tracking {

class MotionModel {
 public:
  // World-to-camera pose at `timestamp`, from the last tracked frame's pose and stamp. Needs a
  // velocity (has_velocity()).
  [[nodiscard]] Eigen::Isometry3d predict(const Eigen::Isometry3d& last_T_cw, double last_timestamp,
                                          double timestamp) const;
  // A frame was tracked at `T_cw`, `timestamp` after the last one at `last_T_cw`, `last_timestamp`.
  void update(const Eigen::Isometry3d& T_cw, double timestamp, const Eigen::Isometry3d& last_T_cw,
              double last_timestamp);
  void reset() { velocity_.reset(); }

  [[nodiscard]] bool has_velocity() const { return velocity_.has_value(); }
  // T_c(t) c(t-1), over one camera frame.
  [[nodiscard]] const Eigen::Isometry3d& velocity() const { return *velocity_; }
  // Seconds between camera frames: measured, or 1 / `fps` until two frames in a row were tracked.
  [[nodiscard]] double frame_period(double fps) const {
    return frame_period_ > 0.0 ? frame_period_ : 1.0 / fps;
  }

 private:
  // Camera frames from `from` to `to`: more than one where frames were dropped (a live node behind
  // the camera) or are missing from a sequence.
  [[nodiscard]] int frame_steps(double from, double to) const;

  std::optional<Eigen::Isometry3d> velocity_;
  double frame_period_ = 0.0;  // 0: not yet known
};

}  // namespace lrd::tracking
