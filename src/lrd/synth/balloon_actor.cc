#include "lrd/synth/balloon_actor.h"

#include <algorithm>
#include <cmath>

#include "lrd/synth/easing.h"
#include "lrd/synth/room_scene.h"
#include "lrd/synth/walking_actor.h"

namespace lrd::synth {
namespace {

constexpr float kHoldReach = 0.38f;  // the held balloon ahead of the person's feet

// A sphere as a stack of tapered prisms (rings of latitude) about `pose`'s z axis; `pose`'s origin
// is the centre. Its texture turns with the pose, so a spinning balloon shows it.
void add_sphere(TriangleSoup& soup, const Eigen::Isometry3f& pose, float radius, const SurfaceStyle& style) {
  constexpr int kRings = 8, kSides = 14;
  for (int k = 0; k < kRings; ++k) {
    const float a0 = static_cast<float>(M_PI) * static_cast<float>(k) / kRings;
    const float a1 = static_cast<float>(M_PI) * static_cast<float>(k + 1) / kRings;
    const float z0 = -radius * std::cos(a0), z1 = -radius * std::cos(a1);
    const float r0 = std::max(0.004f, radius * std::sin(a0)), r1 = std::max(0.004f, radius * std::sin(a1));
    Eigen::Isometry3f ring = pose;
    ring.translate(Eigen::Vector3f(0, 0, z0));
    soup.add_prism(ring, r0, r0, r1, r1, z1 - z0, kSides, style);
  }
}

}  // namespace

BalloonActor::BalloonActor(BalloonParams params, Appearance first_look, Appearance second_look,
                           const TextureLibrary& tex, std::string name)
    : params_(params),
      looks_{first_look, second_look},
      balloon_texture_(tex.id("balloon")),
      name_(std::move(name)) {}

Eigen::Vector3f BalloonActor::held_at(int person) const {
  const Eigen::Vector2f me = person == 0 ? params_.first : params_.second;
  const Eigen::Vector2f other = person == 0 ? params_.second : params_.first;
  const Eigen::Vector2f xy = me + kHoldReach * (other - me).normalized();
  return {xy.x(), xy.y(), 1.32f * looks_[person].height / 1.75f};
}

Eigen::Vector3f BalloonActor::balloon_at(double t) const {
  double c = std::fmod(t + params_.start, period());
  if (c < 0.0) c += period();
  // Held by the first person, flying to the second, held, flying back.
  const double half = params_.flight + params_.hold;
  const int thrower = c < half ? 0 : 1;
  const double into = c < half ? c : c - half;
  if (into < params_.hold) return held_at(thrower);
  const auto s = static_cast<float>((into - params_.hold) / params_.flight);
  const Eigen::Vector3f from = held_at(thrower), to = held_at(1 - thrower);
  const Eigen::Vector3f along = to - from;
  const Eigen::Vector3f side = Eigen::Vector3f::UnitZ().cross(along).normalized();
  const float bow = 4.0f * s * (1.0f - s);
  // A balloon slows in the air: it covers ground fast after the throw and drifts in at the end.
  const float ground = 1.0f - (1.0f - s) * (1.0f - s) * (1.0f - 0.6f * s);
  return from + ground * along + bow * params_.apex * Eigen::Vector3f::UnitZ() +
         (thrower == 0 ? 1.0f : -1.0f) * bow * params_.drift * side;
}

BodyPose BalloonActor::person_pose(int person, double t) const {
  const Eigen::Vector2f me = person == 0 ? params_.first : params_.second;
  const Eigen::Vector2f other = person == 0 ? params_.second : params_.first;
  const float yaw = std::atan2(other.y() - me.y(), other.x() - me.x());
  BodyPose pose = walking_body(floor_pose(me.x(), me.y(), yaw), 0.0f, 0.0f, static_cast<float>(t),
                               params_.phase + static_cast<float>(person), CarriedProp::kNone);
  // How far the arms are raised: fully while this person holds the balloon, rising over the last
  // half second of its flight towards them, falling over the first half second of the throw.
  double c = std::fmod(t + params_.start, period());
  if (c < 0.0) c += period();
  const double half = params_.flight + params_.hold;
  const double mine = person == 0 ? c : std::fmod(c + half, period());  // 0 = I start holding
  double raise = 0.0;
  if (mine < params_.hold) {
    raise = 1.0;
  } else if (mine < params_.hold + 0.5) {
    raise = 1.0 - smoothstep((mine - params_.hold) / 0.5);
  } else if (mine > period() - 0.5) {
    raise = smoothstep((mine - (period() - 0.5)) / 0.5);
  }
  const auto r = static_cast<float>(raise);
  for (std::size_t i = 0; i < 2; ++i) {
    pose.shoulder_pitch[i] = 0.1f + 1.15f * r;
    pose.elbow[i] = 0.2f + 0.35f * r;
    pose.shoulder_roll[i] = 0.05f + 0.1f * r;
  }
  pose.head_pitch = -0.15f * r;
  return pose;
}

void BalloonActor::add_geometry(double t, TriangleSoup& soup) const {
  for (int person = 0; person < 2; ++person) add_humanoid(soup, person_pose(person, t), looks_[person]);
  SurfaceStyle rubber;
  rubber.texture = balloon_texture_;
  rubber.metres_per_repeat = 0.5f;
  rubber.albedo = 1.1f;
  rubber.voc_class = voc::kBackground;  // no Pascal VOC class: a network trained on it cannot know it
  rubber.label = MaskLabel::kBalloon;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = balloon_at(t);
  // It spins slowly as it flies.
  pose.rotate(Eigen::AngleAxisf(0.4f, Eigen::Vector3f::UnitX()));
  pose.rotate(Eigen::AngleAxisf(1.3f * static_cast<float>(t), Eigen::Vector3f::UnitZ()));
  add_sphere(soup, pose, params_.radius, rubber);
}

std::string BalloonActor::describe() const {
  return name_ + ": two people " + std::to_string((params_.second - params_.first).norm()).substr(0, 4) +
         " m apart throw a balloon to each other, every " + std::to_string(period()).substr(0, 4) + " s";
}

}  // namespace lrd::synth
