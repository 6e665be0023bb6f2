#include "lrd/synth/box_mover_actor.h"

#include <algorithm>
#include <cmath>

#include "lrd/synth/easing.h"
#include "lrd/synth/furniture.h"
#include "lrd/synth/room_scene.h"
#include "lrd/synth/walking_actor.h"

namespace lrd::synth {
namespace {

constexpr float kReach = 0.4f;  // the carried box's centre ahead of the person's feet (walking_actor)

float heading(const Eigen::Vector2f& from, const Eigen::Vector2f& to) {
  const Eigen::Vector2f d = to - from;
  return std::atan2(d.y(), d.x());
}

// The angle from `a` to `b` the short way round.
float turn_angle(float a, float b) {
  const auto pi = static_cast<float>(M_PI);
  float d = std::fmod(b - a + pi, 2.0f * pi);
  if (d < 0.0f) d += 2.0f * pi;
  return d - pi;
}

}  // namespace

BoxMoverActor::BoxMoverActor(BoxMoveParams params, Appearance look, const TextureLibrary& tex,
                             std::string name)
    : params_(std::move(params)), look_(look), tex_(tex), name_(std::move(name)) {
  at_ = params_.home;
  yaw_ = heading(params_.home, params_.spot_a);
  add_move(params_.spot_a, params_.spot_b, 0);
  add_move(params_.spot_b, params_.spot_a, 1);
  for (const Step& s : steps_) period_ += s.duration;
}

void BoxMoverActor::add_walk(const Eigen::Vector2f& to, bool carrying, int box_spot) {
  add_turn(heading(at_, to), carrying, box_spot);
  const double length = (to - at_).norm();
  steps_.push_back({StepKind::kWalk, at_, to, yaw_, yaw_, length / params_.speed, carrying, box_spot});
  at_ = to;
}

void BoxMoverActor::add_turn(float yaw, bool carrying, int box_spot) {
  const float d = turn_angle(yaw_, yaw);
  if (std::abs(d) < 1e-3f) return;
  // Half a turn takes kTurnSeconds; smaller ones take less.
  const double duration = kTurnSeconds * std::abs(d) / M_PI + 0.2;
  steps_.push_back({StepKind::kTurn, at_, at_, yaw_, yaw_ + d, duration, carrying, box_spot});
  yaw_ += d;
}

void BoxMoverActor::add_move(const Eigen::Vector2f& from, const Eigen::Vector2f& to, int from_spot) {
  // The person stands behind the box, facing where it goes, lifts it, carries it until it hangs
  // over its new place, puts it down, walks home and waits.
  const Eigen::Vector2f u = (to - from).normalized();
  const int to_spot = 1 - from_spot;
  add_walk(from - kReach * u, false, from_spot);
  add_turn(std::atan2(u.y(), u.x()), false, from_spot);
  steps_.push_back({StepKind::kLift, at_, at_, yaw_, yaw_, kLiftSeconds, true, from_spot});
  add_walk(to - kReach * u, true, from_spot);
  steps_.push_back({StepKind::kLower, at_, at_, yaw_, yaw_, kLiftSeconds, true, to_spot});
  add_walk(params_.home, false, to_spot);
  steps_.push_back({StepKind::kWait, at_, at_, yaw_, yaw_, params_.wait, false, to_spot});
}

BoxMoverActor::Moment BoxMoverActor::moment_at(double t) const {
  double c = std::fmod(t + params_.start, period_);
  if (c < 0.0) c += period_;
  for (const Step& s : steps_) {
    if (c < s.duration) return {&s, c};
    c -= s.duration;
  }
  return {&steps_.back(), steps_.back().duration};
}

float BoxMoverActor::carry_height() const {
  return 1.0f * look_.height / 1.75f;
}

BoxMoverActor::BoxState BoxMoverActor::box_at(double t) const {
  const auto [step, into] = moment_at(t);
  const float floor_z = 0.5f * params_.box_size.z();
  BoxState box;
  if (!step->carrying) {
    const Eigen::Vector2f& spot = step->box_at_spot == 0 ? params_.spot_a : params_.spot_b;
    // At rest it lies as it was put down: along the line between the spots.
    box.centre = Eigen::Vector3f(spot.x(), spot.y(), floor_z);
    box.yaw = heading(params_.spot_a, params_.spot_b);
    return box;
  }
  const float f = static_cast<float>(into / step->duration);
  const Eigen::Vector2f feet = step->from + f * (step->to - step->from);
  const Eigen::Vector2f ahead(std::cos(step->yaw_from), std::sin(step->yaw_from));
  const Eigen::Vector2f xy = feet + kReach * ahead;
  float z = carry_height();
  if (step->kind == StepKind::kLift)
    z = floor_z + (carry_height() - floor_z) * smoothstep(into / step->duration);
  if (step->kind == StepKind::kLower)
    z = carry_height() - (carry_height() - floor_z) * smoothstep(into / step->duration);
  box.centre = Eigen::Vector3f(xy.x(), xy.y(), z);
  box.yaw = step->yaw_from;
  box.moving = true;
  return box;
}

void BoxMoverActor::add_geometry(double t, TriangleSoup& soup) const {
  const auto [step, into] = moment_at(t);
  const double f = step->duration > 0.0 ? into / step->duration : 0.0;
  const auto tf = static_cast<float>(t);
  const Eigen::Vector2f p = step->from + static_cast<float>(f) * (step->to - step->from);
  const float yaw = step->yaw_from + smoothstep(f) * (step->yaw_to - step->yaw_from);
  const CarriedProp prop = step->carrying ? CarriedProp::kCarriedBox : CarriedProp::kNone;
  BodyPose pose;
  if (step->kind == StepKind::kWalk) {
    const float length = (step->to - step->from).norm();
    const float s = static_cast<float>(f) * length;
    const float stride = 1.35f * look_.height / 1.75f;
    const float amp = std::min(1.0f, std::min(s, length - s) / 0.4f);
    pose = walking_body(floor_pose(p.x(), p.y(), yaw), 2.0f * static_cast<float>(M_PI) * s / stride, amp, tf,
                        params_.phase, prop);
  } else {
    pose = walking_body(floor_pose(p.x(), p.y(), yaw), 0.0f, 0.0f, tf, params_.phase, prop);
  }
  // Bending over the box while it is low: the torso leans in as it goes down.
  if (step->kind == StepKind::kLift || step->kind == StepKind::kLower) {
    const float low = step->kind == StepKind::kLift ? 1.0f - smoothstep(f) : smoothstep(f);
    pose.torso_pitch += 0.55f * low;
    pose.head_pitch += 0.3f * low;
    for (std::size_t i = 0; i < 2; ++i) pose.shoulder_pitch[i] += 0.3f * low;
  }
  add_humanoid(soup, pose, look_);
  const BoxState box = box_at(t);
  Eigen::Isometry3f box_pose = floor_pose(box.centre.x(), box.centre.y(), box.yaw, box.centre.z());
  furniture::add_carton(soup, tex_, box_pose, params_.box_size,
                        box.moving ? MaskLabel::kMovedObject : MaskLabel::kStatic);
}

std::string BoxMoverActor::describe() const {
  const float distance = (params_.spot_b - params_.spot_a).norm();
  return name_ + ": carries a box " + std::to_string(distance).substr(0, 4) +
         " m, puts it down, walks away; carries it back; every " + std::to_string(period_).substr(0, 4) +
         " s";
}

}  // namespace lrd::synth
