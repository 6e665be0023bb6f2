#pragma once
// A trajectory's motion as TUM RGB-D's dataset page states it for every sequence (its statistics
// script): duration, length, and mean translational and angular velocity, all from the relative
// motion over 1-second windows (each pose against the one closest to a second later), so
// oscillations faster than a second count less than their instantaneous speed.
#include "lrd/io/trajectory.h"

namespace lrd::eval {

struct MotionStatistics {
  double duration = 0.0;            // s, last minus first stamp
  double length = 0.0;              // m: the 1-s displacements summed over stamps / mean rate
  double mean_speed = 0.0;          // m/s: mean 1-s displacement
  double mean_angular_speed = 0.0;  // deg/s: mean 1-s rotation angle
};

// Needs at least two poses more than a second apart; otherwise all zero.
[[nodiscard]] MotionStatistics motion_statistics(const io::Trajectory& trajectory);

}  // namespace lrd::eval
