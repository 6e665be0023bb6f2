#include "lrd/synth/jumping_actor.h"

#include <algorithm>
#include <cmath>

#include "lrd/synth/room_scene.h"
#include "lrd/synth/walking_actor.h"

namespace lrd::synth {
namespace {

constexpr float kLegLength = 0.85f;  // thigh + shin of a 1.75 m person (humanoid.cc)
// Each jump: a crouch, take-off and flight, landing into a crouch, standing up (fractions of it).
constexpr double kFlightFrom = 0.3, kFlightTo = 0.7;

}  // namespace

JumpingActor::JumpingActor(JumpParams params, Appearance look, std::string name)
    : params_(params), look_(look), name_(std::move(name)) {}

double JumpingActor::jump_phase(double t) const {
  double c = std::fmod(t + params_.start, period());
  if (c < 0.0) c += period();
  if (c >= params_.jumps_per_set * params_.period) return -1.0;
  return std::fmod(c, params_.period) / params_.period;
}

float JumpingActor::lift_at(double t) const {
  const double u = jump_phase(t);
  if (u < kFlightFrom || u > kFlightTo) return 0.0f;
  const double s = (u - kFlightFrom) / (kFlightTo - kFlightFrom);
  return params_.height * static_cast<float>(4.0 * s * (1.0 - s));  // a ballistic arc
}

void JumpingActor::add_geometry(double t, TriangleSoup& soup) const {
  const double u = jump_phase(t);
  // Knee bend: deepest just before take-off and just after landing, straight in the air.
  float crouch = 0.0f;
  if (u >= 0.0 && u < kFlightFrom) crouch = static_cast<float>(std::sin(M_PI * u / kFlightFrom));
  if (u > kFlightTo) crouch = static_cast<float>(std::sin(M_PI * (u - kFlightTo) / (1.0 - kFlightTo)));
  const float bend = 0.55f * crouch;  // rad at the hip; the knee bends twice as far
  const float lift = lift_at(t);
  BodyPose pose = walking_body(floor_pose(params_.spot.x(), params_.spot.y(), params_.yaw, lift), 0.0f, 0.0f,
                               static_cast<float>(t), params_.phase, CarriedProp::kNone);
  pose.pelvis_height -= kLegLength * (1.0f - std::cos(bend));
  for (std::size_t i = 0; i < 2; ++i) {
    pose.hip_pitch[i] = bend;
    pose.knee[i] = 2.0f * bend;
    // Arms swing back in the crouch and up in the air.
    const float air = params_.height > 0.0f ? lift / params_.height : 0.0f;
    pose.shoulder_pitch[i] = -0.5f * crouch + 1.6f * air;
    pose.elbow[i] = 0.2f + 0.2f * crouch;
  }
  pose.torso_pitch = 0.25f * crouch;
  add_humanoid(soup, pose, look_);
}

std::string JumpingActor::describe() const {
  return name_ + ": jumps in sets of " + std::to_string(params_.jumps_per_set) + ", one every " +
         std::to_string(params_.period).substr(0, 4) + " s, resting " +
         std::to_string(params_.rest).substr(0, 3) + " s between sets";
}

}  // namespace lrd::synth
