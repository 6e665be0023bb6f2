#pragma once
// The realism profile's camera motion (docs/synthetic-benchmark.md): each walking/sitting preset's
// smooth path made as fast as the TUM fr3 sequence it mirrors, by TUM's own statistics
// (eval/motion_statistics.h). A real hand-held Kinect turns far more than our smooth paths (5-7x on
// xyz and halfsphere) and the rpy camera also translates, so a time scale cannot match both speeds:
// the path's displacement is scaled down, or a slow wander added, until the translational speed
// matches, then a slow yaw/pitch/roll sway is added until the angular speed does.
#include <optional>
#include <string>

#include "lrd/synth/camera_motion.h"

namespace lrd::synth {

// Mean translational (m/s) and angular (deg/s) velocity over 1-s windows, as TUM's dataset page
// states them for each sequence.
struct MotionTarget {
  double mean_speed = 0.0;
  double mean_angular_speed = 0.0;
};

// The published figures of the fr3 sequence a preset mirrors (TUM RGB-D dataset page, "fr3/
// walking_xyz" etc.; Sturm et al. 2012); none for presets that mirror no fr3 sequence.
[[nodiscard]] std::optional<MotionTarget> tum_fr3_motion(const std::string& preset);

// The hand-held motion that gives `smooth` (the path session 1 renders, sampled at `fps` over
// `duration` seconds) the target's statistics. A speed the smooth path already exceeds by rotation
// alone is left as it is (no sway); translation is scaled down when the path is too fast.
[[nodiscard]] HandHeldMotion match_motion(const CameraMotion& smooth, const MotionTarget& target,
                                          double duration, double fps);

}  // namespace lrd::synth
