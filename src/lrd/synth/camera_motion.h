#pragma once
// Camera trajectories of the synthetic presets, mirroring TUM fr3's: nearly still, translating
// along x/y/z, rotating in roll/pitch/yaw, moving on a half sphere, and circling the room twice.
// Every pose is a smooth function of time plus a small hand-held tremor.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

namespace lrd::synth {

enum class MotionKind { kStill, kXyz, kRpy, kHalfsphere, kLoop };

class CameraMotion {
 public:
  // `duration`: the preset's full length in seconds (the loop's two laps span it).
  CameraMotion(MotionKind kind, double duration, std::uint64_t seed);
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
  MotionKind kind_;
  double duration_;
  std::array<double, 12> phase_{};
};

}  // namespace lrd::synth
