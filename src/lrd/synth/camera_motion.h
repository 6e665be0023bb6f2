#pragma once
// Camera trajectories of the synthetic presets, mirroring TUM fr3's: nearly still, translating
// along x/y/z, rotating in roll/pitch/yaw, moving on a half sphere, and circling the room twice;
// and the long presets' laps of the room for as long as the sequence lasts (kTour: radius and
// height drifting; kCircle: the same circle every lap).
// Every pose is a smooth function of time plus a small hand-held tremor.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

namespace lrd::synth {

enum class MotionKind { kStill, kXyz, kRpy, kHalfsphere, kLoop, kTour, kCircle };

class CameraMotion {
 public:
  // `duration`: the preset's full length in seconds (the loop's two laps span it). `session` 1 is
  // the preset's path; 2 and 3 are the same motion from another standpoint (map-file sessions,
  // issue 20): the camera stands 0.6 m aside and starts turned 80 deg away from session 1's view
  // (2: to the left, 3: to the right), then over its first 4 s turns to within 12 deg of it, so
  // it first sees what session 1 did not and then overlaps session 1's view in part.
  CameraMotion(MotionKind kind, double duration, std::uint64_t seed, int session = 1);
  static constexpr int kMaxSession = 3;
  static constexpr double kTourLap = 20.0;  // s, one lap of kTour and kCircle
  // Camera-to-world pose (camera: x right, y down, z forward; world: z up).
  [[nodiscard]] Eigen::Isometry3d pose_at(double t) const;
  [[nodiscard]] MotionKind kind() const { return kind_; }

  // Pose at `position` looking at `target`, world z up, then rotated by yaw/pitch/roll in the
  // camera frame.
  static Eigen::Isometry3d look_at(const Eigen::Vector3d& position, const Eigen::Vector3d& target,
                                   double yaw = 0, double pitch = 0, double roll = 0);

 private:
  [[nodiscard]] Eigen::Vector3d tremor_position(double t) const;
  [[nodiscard]] Eigen::Vector3d tremor_angles(double t) const;
  // World-frame motion from session 1's standpoint to this session's at time t.
  [[nodiscard]] Eigen::Isometry3d session_offset(double t) const;
  MotionKind kind_;
  int session_;
  double duration_;
  std::array<double, 12> phase_{};
};

}  // namespace lrd::synth
