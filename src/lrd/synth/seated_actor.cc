#include "lrd/synth/seated_actor.h"

#include <cmath>

namespace lrd::synth {

SeatedActor::SeatedActor(const Eigen::Isometry3f& seat, Appearance look, float phase, float liveliness,
                         std::string name)
    : seat_(seat), look_(look), phase_(phase), liveliness_(liveliness), name_(std::move(name)) {}

void SeatedActor::add_geometry(double t, TriangleSoup& soup) const {
  add_humanoid(soup, pose_at(t), look_);
}

BodyPose SeatedActor::pose_at(double t) const {
  const float tf = static_cast<float>(t), ph = phase_, L = liveliness_;
  BodyPose pose;
  pose.root = seat_;
  // Shifting on the seat (a few cm) and leaning.
  pose.root.translate(
      Eigen::Vector3f(0.03f * std::sin(0.21f * tf + ph) * L, 0.04f * std::sin(0.13f * tf + 2 * ph) * L, 0));
  pose.pelvis_height = 0.55f;
  pose.torso_pitch = 0.08f + 0.12f * std::sin(0.31f * tf + ph) * L;
  pose.torso_roll = 0.07f * std::sin(0.17f * tf + 3 * ph) * L;
  pose.torso_yaw = 0.4f * std::sin(0.19f * tf + ph) * L;  // turning to talk to the neighbour
  pose.head_yaw = 0.5f * std::sin(0.29f * tf + 1.7f * ph) * L;
  pose.head_pitch = 0.15f * std::sin(0.41f * tf + ph);
  for (std::size_t i = 0; i < 2; ++i) {
    const float s = i == 0 ? 1.0f : -1.0f;
    pose.hip_pitch[i] = 1.5f;
    pose.knee[i] = 1.45f + 0.1f * std::sin(0.23f * tf + s * ph);
    pose.hip_roll[i] = 0.08f;
    // Gestures: bursts of arm movement, each arm on its own rhythm.
    const float burst = std::max(0.0f, std::sin(0.35f * tf + ph + s));
    pose.shoulder_pitch[i] = 0.35f + L * burst * (0.7f + 0.4f * std::sin(2.3f * tf + s * ph));
    pose.shoulder_roll[i] = 0.15f * L * burst * std::sin(1.7f * tf + ph);
    pose.elbow[i] = 1.1f + 0.5f * L * burst * std::sin(3.1f * tf + ph + s);
  }
  return pose;
}

std::string SeatedActor::describe() const {
  return name_ + ": seated, shifting, turning and gesturing";
}

}  // namespace lrd::synth
