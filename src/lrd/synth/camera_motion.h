#pragma once
// Camera trajectories of the synthetic presets, mirroring TUM fr3's: nearly still, translating
// along x/y/z, rotating in roll/pitch/yaw, moving on a half sphere, and circling the room twice;
// and the long presets' laps of the room for as long as the sequence lasts (kTour: radius and
// height drifting; kCircle: the same circle every lap).
// kFollow walks behind a person, looking at them (Bonn's person_tracking).
// Every pose is a smooth function of time plus a small hand-held tremor.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>

namespace lrd::synth {

enum class MotionKind { kStill, kXyz, kRpy, kHalfsphere, kLoop, kTour, kCircle, kFollow };

// How the realism profile's hand-held camera departs from a preset's smooth path
// (docs/synthetic-benchmark.md; synth/motion_matching.h sizes it for each preset). The defaults are
// the smooth path itself.
struct HandHeldMotion {
  double path_scale = 1.0;        // the path's displacement from the presets' standpoint, scaled
  double translation_sway = 0.0;  // m: amplitude of a slow wander (periods of 2-7 s)
  double rotation_sway = 0.0;     // rad: amplitude of a slow yaw/pitch/roll sway (periods of 2-8 s)
};

class CameraMotion {
 public:
  // `duration`: the preset's full length in seconds (the loop's two laps span it). `session` 1 is
  // the preset's path; 2 and 3 are the same motion from another standpoint (map-file sessions,
  // docs/map-files.md): the camera stands 0.6 m aside and starts turned 80 deg away from the view
  // session 1 sees (2: to the left, 3: to the right), then over its first 4 s turns to within
  // 12 deg of it, so it first sees what the first map-file session did not and then overlaps that
  // session's view in part.
  CameraMotion(MotionKind kind, double duration, std::uint64_t seed, int session = 1);
  static constexpr int kMaxSession = 3;
  static constexpr double kTourLap = 20.0;  // s, one lap of kTour and kCircle
  // Camera-to-world pose (camera: x right, y down, z forward; world: z up).
  [[nodiscard]] Eigen::Isometry3d pose_at(double t) const;
  [[nodiscard]] MotionKind kind() const { return kind_; }
  // Only for the presets standing at the walking/sitting standpoint (kStill, kXyz, kRpy,
  // kHalfsphere): the path is scaled about it.
  void set_hand_held(const HandHeldMotion& motion) { hand_held_ = motion; }
  [[nodiscard]] const HandHeldMotion& hand_held() const { return hand_held_; }
  // kFollow: where the followed person stands (floor, world) at time t. The camera is carried
  // along their path kFollowLag seconds behind them, looking at their back.
  using FollowTarget = std::function<Eigen::Vector2f(double)>;
  void set_follow(FollowTarget target) { follow_ = std::move(target); }
  static constexpr double kFollowLag = 1.9;

  // Pose at `position` looking at `target`, world z up, then rotated by yaw/pitch/roll in the
  // camera frame.
  static Eigen::Isometry3d look_at(const Eigen::Vector3d& position, const Eigen::Vector3d& target,
                                   double yaw = 0, double pitch = 0, double roll = 0);

 private:
  [[nodiscard]] Eigen::Isometry3d smooth_pose_at(double t) const;
  [[nodiscard]] Eigen::Isometry3d hand_held_pose(const Eigen::Isometry3d& smooth, double t) const;
  [[nodiscard]] Eigen::Vector3d tremor_position(double t) const;
  [[nodiscard]] Eigen::Vector3d tremor_angles(double t) const;
  // World-frame motion from the standpoint of map-file session 1 to this session's at time t.
  [[nodiscard]] Eigen::Isometry3d session_offset(double t) const;
  MotionKind kind_;
  int session_;
  double duration_;
  std::array<double, 12> phase_{};
  HandHeldMotion hand_held_;
  std::array<double, 12> sway_phase_{};  // drawn apart from phase_: the smooth paths stay as they were
  FollowTarget follow_;
};

}  // namespace lrd::synth
