#include "lrd/synth/walking_actor.h"

#include <algorithm>
#include <cmath>

#include "lrd/synth/furniture.h"
#include "lrd/synth/room_scene.h"

namespace lrd::synth {

BodyPose walking_body(const Eigen::Isometry3f& root, float phi, float amp, float tf, float phase,
                      CarriedProp prop) {
  const bool pushing = prop == CarriedProp::kPushedChair;
  const bool carrying = prop == CarriedProp::kCarriedBox;
  BodyPose pose;
  pose.root = root;
  pose.pelvis_height = 0.93f - 0.015f * std::abs(std::cos(phi)) * amp;
  pose.torso_yaw = 0.06f * std::sin(phi) * amp;
  pose.torso_pitch = pushing ? 0.25f : 0.04f;
  pose.head_yaw = 0.35f * std::sin(0.37f * tf + phase);
  pose.head_pitch = 0.1f * std::sin(0.23f * tf + 2.0f * phase);
  for (int i = 0; i < 2; ++i) {
    const float sgn = i == 0 ? 1.0f : -1.0f;
    const float leg = sgn * std::sin(phi);
    pose.hip_pitch[static_cast<std::size_t>(i)] = 0.38f * leg * amp;
    pose.knee[static_cast<std::size_t>(i)] = (0.08f + 0.6f * std::max(0.0f, sgn * std::cos(phi))) * amp;
    if (pushing) {
      pose.shoulder_pitch[static_cast<std::size_t>(i)] = 1.05f;
      pose.elbow[static_cast<std::size_t>(i)] = 0.45f;
    } else if (carrying) {
      pose.shoulder_pitch[static_cast<std::size_t>(i)] = 0.75f;
      pose.elbow[static_cast<std::size_t>(i)] = 1.0f;
      pose.shoulder_roll[static_cast<std::size_t>(i)] = 0.15f;
    } else {
      pose.shoulder_pitch[static_cast<std::size_t>(i)] = -0.4f * leg * amp;
      pose.elbow[static_cast<std::size_t>(i)] = 0.25f + 0.2f * std::max(0.0f, -leg) * amp;
    }
  }
  return pose;
}

BodyPose walk_leg_body(const Eigen::Isometry3f& root, float s, float length, const Appearance& look, float tf,
                       float phase) {
  s = std::clamp(s, 0.0f, length);
  const float stride = 1.35f * look.height / 1.75f;
  const float phi = 2.0f * static_cast<float>(M_PI) * s / stride;
  const float amp = std::min(1.0f, std::min(s, length - s) / 0.4f);
  return walking_body(root, phi, amp, tf, phase, CarriedProp::kNone);
}

WalkingActor::WalkingActor(WalkingParams params, Appearance look, const TextureLibrary& tex, std::string name)
    : params_(std::move(params)), look_(look), tex_(tex), path_(params_.waypoints), name_(std::move(name)) {}

namespace {
constexpr float kSpeedOmega = 2.0f * static_cast<float>(M_PI) / 9.0f;  // speed oscillation, 9 s period
}

float WalkingActor::arc_length(float tf) const {
  const float w = kSpeedOmega;
  const float a = params_.speed_variation;
  // Integral of v (1 + a cos(w t + phase)): keeps the speed positive for a < 1.
  return params_.start +
         params_.speed * (tf + a * (std::sin(w * tf + params_.phase) - std::sin(params_.phase)) / w);
}

Eigen::Vector2f WalkingActor::floor_position(double t) const {
  Eigen::Vector2f p, h;
  path_.at(arc_length(static_cast<float>(t)), p, h);
  return p;
}

void WalkingActor::add_geometry(double t, TriangleSoup& soup) const {
  const float tf = static_cast<float>(t);
  const float w = kSpeedOmega;
  const float a = params_.speed_variation;
  const float s = arc_length(tf);
  Eigen::Vector2f p, h;
  path_.at(s, p, h);
  const float yaw = std::atan2(h.y(), h.x());
  const bool pushing = params_.prop == CarriedProp::kPushedChair;
  const bool carrying = params_.prop == CarriedProp::kCarriedBox;
  const float stride = (pushing ? 1.0f : 1.35f) * look_.height / 1.75f;
  const float phi = 2.0f * static_cast<float>(M_PI) * s / stride;
  const float speed_now = params_.speed * (1.0f + a * std::cos(w * tf + params_.phase));
  const float amp = std::min(1.0f, speed_now / 0.8f);  // slower walking, smaller swings

  const BodyPose pose =
      walking_body(floor_pose(p.x(), p.y(), yaw), phi, amp, tf, params_.phase, params_.prop);
  add_humanoid(soup, pose, look_);

  if (pushing) {
    // The chair rolls ahead of the person, backrest towards them.
    Eigen::Isometry3f chair = pose.root;
    chair.translate(Eigen::Vector3f(0.62f * look_.height / 1.75f, 0, 0));
    furniture::add_chair(soup, tex_, chair, MaskLabel::kMovedObject);
  } else if (carrying) {
    Eigen::Isometry3f box = pose.root;
    box.translate(Eigen::Vector3f(0.4f, 0, 1.0f * look_.height / 1.75f));
    furniture::add_carton(soup, tex_, box, {0.32f, 0.42f, 0.3f}, MaskLabel::kMovedObject);
  }
}

std::string WalkingActor::describe() const {
  const char* prop = params_.prop == CarriedProp::kPushedChair  ? " pushing a chair"
                     : params_.prop == CarriedProp::kCarriedBox ? " carrying a box"
                                                                : "";
  return name_ + ": walking a " + std::to_string(path_.length()).substr(0, 4) + " m loop at " +
         std::to_string(params_.speed).substr(0, 4) + " m/s" + prop;
}

}  // namespace lrd::synth
