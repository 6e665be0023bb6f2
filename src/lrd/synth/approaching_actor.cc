#include "lrd/synth/approaching_actor.h"

#include <cmath>

#include "lrd/synth/room_scene.h"
#include "lrd/synth/walking_actor.h"

namespace lrd::synth {

ApproachingActor::ApproachingActor(ApproachParams params, Appearance look, std::string name)
    : params_(params), look_(look), name_(std::move(name)) {}

double ApproachingActor::period() const {
  const double walk = (params_.near - params_.far).norm() / params_.speed;
  return 2.0 * walk + params_.hold + params_.wait + 2.0 * kTurnSeconds;
}

void ApproachingActor::add_geometry(double t, TriangleSoup& soup) const {
  const Eigen::Vector2f line = params_.near - params_.far;
  const float length = line.norm();
  const float towards = std::atan2(line.y(), line.x());  // facing the camera on the way there
  const float pi = static_cast<float>(M_PI);
  const double walk = length / params_.speed;
  double c = std::fmod(t + params_.start, period());
  // Distance from `far` and heading, through the cycle's six parts.
  float s = 0.0f, yaw = towards;
  if (c < walk) {
    s = params_.speed * static_cast<float>(c);
  } else if ((c -= walk) < params_.hold) {
    s = length;
  } else if ((c -= params_.hold) < kTurnSeconds) {
    s = length;
    yaw = towards + pi * static_cast<float>(c / kTurnSeconds);
  } else if ((c -= kTurnSeconds) < walk) {
    s = length - params_.speed * static_cast<float>(c);
    yaw = towards + pi;
  } else if ((c -= walk) < kTurnSeconds) {
    yaw = towards + pi + pi * static_cast<float>(c / kTurnSeconds);
  }
  const Eigen::Vector2f p = params_.far + (s / length) * line;
  // Standing (s at either end) while they hold, turn and wait.
  add_humanoid(
      soup,
      walk_leg_body(floor_pose(p.x(), p.y(), yaw), s, length, look_, static_cast<float>(t), params_.phase),
      look_);
}

std::string ApproachingActor::describe() const {
  return name_ + ": walks " + std::to_string((params_.near - params_.far).norm()).substr(0, 4) +
         " m straight at the camera, stands there " + std::to_string(params_.hold).substr(0, 3) +
         " s, walks back, every " + std::to_string(period()).substr(0, 4) + " s";
}

}  // namespace lrd::synth
