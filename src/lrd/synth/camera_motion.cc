#include "lrd/synth/camera_motion.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "lrd/synth/portable_random.h"
#include "lrd/util/error.h"

namespace lrd::synth {
namespace {
constexpr double kTwoPi = 2.0 * M_PI;
const Eigen::Vector3d kBase(2.2, 2.5, 1.35);    // where the walking/sitting presets' camera stands
const Eigen::Vector3d kTarget(5.2, 2.5, 0.85);  // the desk

// `R` turned by camera-frame rotations: yaw about -y (world up), pitch about x, roll about z
// (multiplied in this order: the clean presets' poses stay bit for bit what they were).
Eigen::Matrix3d turned(const Eigen::Matrix3d& R, double yaw, double pitch, double roll) {
  return R * Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitY()).toRotationMatrix() *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()).toRotationMatrix() *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}
}  // namespace

CameraMotion::CameraMotion(MotionKind kind, double duration, std::uint64_t seed, int session)
    : kind_(kind), session_(session), duration_(duration) {
  if (session < 1 || session > kMaxSession)
    throw Error("synth: session " + std::to_string(session) + " (sessions are 1 .. " +
                std::to_string(kMaxSession) + ")");
  PortableRandom rng(seed * 0x2545F4914F6CDD1Dull + 17);
  for (double& p : phase_) p = rng.uniform(0.0, kTwoPi);
  PortableRandom sway_rng(seed * 0x9E3779B97F4A7C15ull + 29);
  for (double& p : sway_phase_) p = sway_rng.uniform(0.0, kTwoPi);
}

Eigen::Isometry3d CameraMotion::look_at(const Eigen::Vector3d& position, const Eigen::Vector3d& target,
                                        double yaw, double pitch, double roll) {
  const Eigen::Vector3d z = (target - position).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = y;
  R.col(2) = z;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = turned(R, yaw, pitch, roll);
  T.translation() = position;
  return T;
}

Eigen::Vector3d CameraMotion::tremor_position(double t) const {
  // A hand-held camera never stands perfectly still: a few millimetres of multi-sine tremor.
  return 0.002 * Eigen::Vector3d(
                     std::sin(kTwoPi * 1.3 * t + phase_[0]) + 0.5 * std::sin(kTwoPi * 3.1 * t + phase_[1]),
                     std::sin(kTwoPi * 1.1 * t + phase_[2]) + 0.5 * std::sin(kTwoPi * 2.7 * t + phase_[3]),
                     std::sin(kTwoPi * 0.9 * t + phase_[4]) + 0.5 * std::sin(kTwoPi * 2.3 * t + phase_[5]));
}

Eigen::Vector3d CameraMotion::tremor_angles(double t) const {
  const double a = 0.003;  // radians (~0.2 degrees)
  return a * Eigen::Vector3d(
                 std::sin(kTwoPi * 0.7 * t + phase_[6]) + 0.5 * std::sin(kTwoPi * 2.9 * t + phase_[7]),
                 std::sin(kTwoPi * 0.8 * t + phase_[8]) + 0.5 * std::sin(kTwoPi * 2.1 * t + phase_[9]),
                 std::sin(kTwoPi * 0.6 * t + phase_[10]) + 0.5 * std::sin(kTwoPi * 1.9 * t + phase_[11]));
}

Eigen::Isometry3d CameraMotion::session_offset(double t) const {
  // A yaw about the vertical through the standpoint, easing from 80 deg to 12 deg over the
  // first 4 s (smoothstep), then a step aside; map-file session 3 mirrors it.
  constexpr double kStartYaw = 80.0 * M_PI / 180.0, kEndYaw = 12.0 * M_PI / 180.0, kTurnSeconds = 4.0;
  const double sign = session_ == 2 ? 1.0 : -1.0;
  const double s = std::clamp(t / kTurnSeconds, 0.0, 1.0);
  const double yaw = sign * (kEndYaw + (kStartYaw - kEndYaw) * (1.0 - s * s * (3.0 - 2.0 * s)));
  const Eigen::Vector3d aside(-0.3, -sign * 0.5, sign * 0.05);
  Eigen::Isometry3d A = Eigen::Isometry3d::Identity();
  A.translate(kBase + aside);
  A.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  A.translate(-kBase);
  return A;
}

Eigen::Isometry3d CameraMotion::pose_at(double t) const {
  if (session_ != 1) {
    CameraMotion first = *this;
    first.session_ = 1;
    return session_offset(t) * first.pose_at(t);
  }
  return hand_held_pose(smooth_pose_at(t), t);
}

Eigen::Isometry3d CameraMotion::hand_held_pose(const Eigen::Isometry3d& smooth, double t) const {
  const HandHeldMotion& h = hand_held_;
  if (h.path_scale == 1.0 && h.translation_sway == 0.0 && h.rotation_sway == 0.0) return smooth;
  // Slow two-tone waves: a hand sways over seconds, which TUM's 1-s statistics count (the fast
  // tremor they mostly average out is already in the smooth path).
  const auto wave = [&](int k, double f1, double f2) {
    return std::sin(kTwoPi * f1 * t + sway_phase_[k]) + 0.5 * std::sin(kTwoPi * f2 * t + sway_phase_[k + 1]);
  };
  Eigen::Isometry3d T = smooth;
  T.translation() = kBase + h.path_scale * (smooth.translation() - kBase) +
                    h.translation_sway *
                        Eigen::Vector3d(wave(0, 0.19, 0.43), wave(2, 0.15, 0.37), 0.6 * wave(4, 0.23, 0.51));
  const double a = h.rotation_sway;
  T.linear() = turned(smooth.linear(), a * wave(6, 0.21, 0.47), 0.7 * a * wave(8, 0.17, 0.41),
                      0.4 * a * wave(10, 0.13, 0.33));
  return T;
}

Eigen::Isometry3d CameraMotion::smooth_pose_at(double t) const {
  const Eigen::Vector3d tp = tremor_position(t);
  const Eigen::Vector3d ta = tremor_angles(t);
  const Eigen::Vector3d forward = (kTarget - kBase).normalized();
  switch (kind_) {
    case MotionKind::kStill: {
      // The "static" TUM sequences still drift by a centimetre or so.
      const Eigen::Vector3d drift(0.006 * std::sin(kTwoPi * t / 11.0 + phase_[0]),
                                  0.008 * std::sin(kTwoPi * t / 13.0 + phase_[1]),
                                  0.004 * std::sin(kTwoPi * t / 9.0 + phase_[2]));
      return look_at(kBase + drift + tp, kTarget, ta.x(), ta.y(), ta.z());
    }
    case MotionKind::kXyz: {
      const Eigen::Vector3d d(0.22 * std::sin(kTwoPi * t / 8.5 + phase_[0]),
                              0.35 * std::sin(kTwoPi * t / 6.3 + phase_[1]),
                              0.15 * std::sin(kTwoPi * t / 7.1 + phase_[2]));
      // Translation with a nearly constant viewing direction, as in TUM's xyz sequences.
      return look_at(kBase + d + tp, kBase + d + 3.0 * forward, ta.x() + 0.02 * std::sin(kTwoPi * t / 5.0),
                     ta.y(), ta.z());
    }
    case MotionKind::kRpy: {
      const double yaw = 0.33 * std::sin(kTwoPi * t / 7.3 + phase_[0]);
      const double pitch = 0.2 * std::sin(kTwoPi * t / 5.9 + phase_[1]);
      const double roll = 0.3 * std::sin(kTwoPi * t / 8.1 + phase_[2]);
      return look_at(kBase + tp, kTarget, yaw + ta.x(), pitch + ta.y(), roll + ta.z());
    }
    case MotionKind::kHalfsphere: {
      // On a half sphere of ~1 m diameter around the standing point, always facing the desk.
      const double az = 1.1 * std::sin(kTwoPi * t / 19.0 + phase_[0]);
      const double el = 0.45 + 0.4 * std::sin(kTwoPi * t / 7.7 + phase_[1]);
      const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(forward).normalized();
      const Eigen::Vector3d up = forward.cross(left);
      const Eigen::Vector3d p = kBase +
                                0.5 * (-std::cos(el) * std::cos(az) * forward +
                                       std::cos(el) * std::sin(az) * left + std::sin(el) * up) +
                                0.5 * forward;
      return look_at(p + tp, kTarget, ta.x(), ta.y(), ta.z());
    }
    case MotionKind::kLoop: {
      // Two laps around a 0.6 m circle in the middle of the room, looking outwards at the walls,
      // returning to the start: the loop-closure presets.
      const Eigen::Vector3d c(2.7, 2.5, 1.35);
      const double theta = kTwoPi * 2.0 * t / duration_;
      const Eigen::Vector3d radial(std::cos(theta), std::sin(theta), 0.0);
      const Eigen::Vector3d p = c + 0.6 * radial + Eigen::Vector3d(0, 0, 0.05 * std::sin(2.0 * theta));
      const Eigen::Vector3d q = p + 2.0 * radial + Eigen::Vector3d(0, 0, -0.35);
      return look_at(p + tp, q, ta.x(), ta.y(), ta.z());
    }
    case MotionKind::kTour:
    case MotionKind::kCircle: {
      // The long presets (bench_scale, bench/results/scale.md): laps of kTourLap seconds around the
      // middle of the room, looking outwards, whatever the length. kTour: radius and height drift
      // between laps (periods of 7.3 and 4.9 laps: under 0.3 m from one lap to the next), so every
      // lap revisits what earlier ones saw (loops) from a slightly different place, at
      // 0.13-0.28 m/s and 18 deg/s (TUM fr3's walking sequences: 0.1-0.4 m/s). kCircle: the same
      // 0.65 m circle every lap (0.2 m/s), where the map should stop growing after the first laps
      // (it grows with the space explored).
      const Eigen::Vector3d c(2.7, 2.5, 1.35);
      const double drift = kind_ == MotionKind::kTour ? 1.0 : 0.0;
      const double theta = kTwoPi * t / kTourLap;
      const double radius = 0.65 + drift * 0.25 * std::sin(kTwoPi * t / (7.3 * kTourLap));
      const double height = drift * 0.15 * std::sin(kTwoPi * t / (4.9 * kTourLap));
      const Eigen::Vector3d radial(std::cos(theta), std::sin(theta), 0.0);
      const Eigen::Vector3d p = c + radius * radial + Eigen::Vector3d(0, 0, height);
      const Eigen::Vector3d q = p + 2.0 * radial + Eigen::Vector3d(0, 0, -0.35);
      return look_at(p + tp, q, ta.x(), ta.y(), ta.z());
    }
    case MotionKind::kFollow: {
      // Held at eye height by someone walking the followed person's path kFollowLag seconds behind
      // them (1-2.5 m as their pace varies), aimed at their shoulders: they stay in the middle of
      // the image for the whole sequence, as in Bonn's person_tracking.
      if (!follow_) throw Error("synth: a following camera needs the person it follows");
      const Eigen::Vector2d behind = follow_(t - kFollowLag).cast<double>();
      const Eigen::Vector2d ahead = follow_(t).cast<double>();
      const Eigen::Vector3d p(behind.x(), behind.y(), 1.45);
      const Eigen::Vector3d q(ahead.x(), ahead.y(), 1.2);
      return look_at(p + tp, q, ta.x(), ta.y(), ta.z());
    }
  }
  return Eigen::Isometry3d::Identity();
}

}  // namespace lrd::synth
