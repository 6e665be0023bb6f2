#include "lrd/synth/standing_up_actor.h"

#include <algorithm>
#include <cmath>

#include "lrd/synth/room_scene.h"
#include "lrd/synth/walking_actor.h"
#include "lrd/util/error.h"

namespace lrd::synth {
namespace {

float yaw_of(const Eigen::Isometry3f& pose) {
  return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
}

// The shortest turn from angle a to angle b.
float turn(float a, float b) {
  const float two_pi = 2.0f * static_cast<float>(M_PI);
  float d = std::fmod(b - a, two_pi);
  if (d > static_cast<float>(M_PI)) d -= two_pi;
  if (d < -static_cast<float>(M_PI)) d += two_pi;
  return d;
}

template <std::size_t N>
std::array<float, N> mix(const std::array<float, N>& a, const std::array<float, N>& b, float u) {
  std::array<float, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = a[i] + u * (b[i] - a[i]);
  return out;
}

}  // namespace

StandingUpActor::StandingUpActor(SeatedActor seated, double stand_at, std::vector<Eigen::Vector2f> exit,
                                 float speed, std::string name)
    : seated_(std::move(seated)),
      stand_at_(stand_at),
      exit_(std::move(exit)),
      speed_(speed),
      name_(std::move(name)) {
  if (exit_.size() < 2) throw Error("synth: a standing-up actor needs an exit of two points or more");
  for (std::size_t i = 1; i < exit_.size(); ++i) exit_length_ += (exit_[i] - exit_[i - 1]).norm();
}

void StandingUpActor::exit_at(float s, Eigen::Vector2f& position, float& yaw) const {
  s = std::clamp(s, 0.0f, exit_length_);
  for (std::size_t i = 1; i < exit_.size(); ++i) {
    const Eigen::Vector2f leg = exit_[i] - exit_[i - 1];
    const float length = leg.norm();
    if (s <= length || i + 1 == exit_.size()) {
      position = exit_[i - 1] + std::min(s / length, 1.0f) * leg;
      yaw = std::atan2(leg.y(), leg.x());
      return;
    }
    s -= length;
  }
}

BodyPose StandingUpActor::rising_pose(double t) const {
  // From the seated pose at the moment of rising to standing at the exit's start, facing along it;
  // the torso leans forward on the way up, as one does to get off a chair.
  const BodyPose sitting = seated_.pose_at(stand_at_);
  Eigen::Vector2f start;
  float exit_yaw = 0.0f;
  exit_at(0.0f, start, exit_yaw);
  const float tf = static_cast<float>(t);
  const BodyPose standing =
      walking_body(floor_pose(start.x(), start.y(), exit_yaw), 0.0f, 0.0f, tf, 0.0f, CarriedProp::kNone);
  const float x = static_cast<float>(std::clamp((t - stand_at_) / kRiseSeconds, 0.0, 1.0));
  const float u = x * x * (3.0f - 2.0f * x);  // smoothstep
  BodyPose pose = standing;
  const Eigen::Vector3f from = sitting.root.translation(), to = standing.root.translation();
  const float yaw = yaw_of(sitting.root) + u * turn(yaw_of(sitting.root), exit_yaw);
  pose.root = floor_pose(from.x() + u * (to.x() - from.x()), from.y() + u * (to.y() - from.y()), yaw);
  const auto lerp = [u](float a, float b) { return a + u * (b - a); };
  pose.pelvis_height = lerp(sitting.pelvis_height, standing.pelvis_height);
  pose.torso_pitch =
      lerp(sitting.torso_pitch, standing.torso_pitch) + 0.5f * std::sin(static_cast<float>(M_PI) * u);
  pose.torso_roll = lerp(sitting.torso_roll, standing.torso_roll);
  pose.torso_yaw = lerp(sitting.torso_yaw, standing.torso_yaw);
  pose.head_pitch = lerp(sitting.head_pitch, standing.head_pitch);
  pose.head_yaw = lerp(sitting.head_yaw, standing.head_yaw);
  pose.hip_pitch = mix(sitting.hip_pitch, standing.hip_pitch, u);
  pose.hip_roll = mix(sitting.hip_roll, standing.hip_roll, u);
  pose.knee = mix(sitting.knee, standing.knee, u);
  pose.shoulder_pitch = mix(sitting.shoulder_pitch, standing.shoulder_pitch, u);
  pose.shoulder_roll = mix(sitting.shoulder_roll, standing.shoulder_roll, u);
  pose.elbow = mix(sitting.elbow, standing.elbow, u);
  return pose;
}

void StandingUpActor::add_geometry(double t, TriangleSoup& soup) const {
  if (t < stand_at_) return seated_.add_geometry(t, soup);
  const double walking_from = stand_at_ + kRiseSeconds;
  if (t < walking_from) {
    add_humanoid(soup, rising_pose(t), seated_.look());
    return;
  }
  const float s = speed_ * static_cast<float>(t - walking_from);
  Eigen::Vector2f p;
  float yaw = 0.0f;
  exit_at(s, p, yaw);
  // At the exit's end they stand still.
  add_humanoid(soup,
               walk_leg_body(floor_pose(p.x(), p.y(), yaw), s, exit_length_, seated_.look(),
                             static_cast<float>(t), 0.0f),
               seated_.look());
}

std::string StandingUpActor::describe() const {
  return seated_.describe() + "; stands up after " + std::to_string(stand_at_).substr(0, 4) +
         " s and walks " + std::to_string(exit_length_).substr(0, 4) + " m out of the view";
}

}  // namespace lrd::synth
