#include "lrd/tracking/motion_model.h"

#include <algorithm>
#include <cmath>

#include "lrd/geometry/se3.h"

namespace lrd::tracking {

int MotionModel::frame_steps(double from, double to) const {
  // Beyond a third of a second at 30 Hz the constant velocity is a guess either way; the
  // reference keyframe and relocalization take over when it fails.
  constexpr long kMaxSteps = 10;
  const double dt = to - from;
  if (frame_period_ <= 0.0 || !(dt > 0.0)) return 1;
  return static_cast<int>(std::clamp(std::lround(dt / frame_period_), 1L, kMaxSteps));
}

Eigen::Isometry3d MotionModel::predict(const Eigen::Isometry3d& last_T_cw, double last_timestamp,
                                       double timestamp) const {
  const int steps = frame_steps(last_timestamp, timestamp);
  if (steps == 1) return *velocity_ * last_T_cw;
  Eigen::Isometry3d T_cw = last_T_cw;
  for (int step = 0; step < steps; ++step) T_cw = *velocity_ * T_cw;
  return geometry::orthonormalized(T_cw);
}

void MotionModel::update(const Eigen::Isometry3d& T_cw, double timestamp, const Eigen::Isometry3d& last_T_cw,
                         double last_timestamp) {
  // The motion per camera frame: one n-th of the motion since the last tracked frame when n-1
  // frames between were dropped. Stamp jitter rounds away, so a sequence without gaps gives the
  // plain frame-to-frame velocity.
  const int steps = frame_steps(last_timestamp, timestamp);
  const Eigen::Isometry3d motion = T_cw * last_T_cw.inverse();
  velocity_ = steps == 1 ? motion : geometry::orthonormalized(geometry::se3_power(motion, 1.0 / steps));
  const double dt = timestamp - last_timestamp;
  if (steps == 1 && dt > 0.0) frame_period_ = dt;
}

}  // namespace lrd::tracking
