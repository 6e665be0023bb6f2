#pragma once
// An articulated humanoid (pelvis, torso, neck, head with hair, upper/lower arms, hands, thighs,
// shins, feet) built from tapered prisms, posed by joint angles.
#include <Eigen/Geometry>
#include <array>

#include "lrd/synth/texture_library.h"
#include "lrd/synth/triangle_soup.h"

namespace lrd::synth {

struct Appearance {
  TextureId shirt = 0, trousers = 0, skin = 0, hair = 0, shoes = 0;
  float height = 1.75f;  // metres; limb lengths scale with it
  float girth = 1.0f;    // width scale
};

// Joint angles in radians. Index 0 = left, 1 = right. Positive pitch moves a limb forward (+x),
// positive knee/elbow flex bends the joint the natural way.
struct BodyPose {
  Eigen::Isometry3f root = Eigen::Isometry3f::Identity();  // on the floor under the pelvis, +x forward
  float pelvis_height = 0.93f;                             // for a 1.75 m person; scaled with the height
  float torso_pitch = 0.0f, torso_roll = 0.0f, torso_yaw = 0.0f;
  float head_pitch = 0.0f, head_yaw = 0.0f;
  std::array<float, 2> hip_pitch{}, hip_roll{}, knee{};
  std::array<float, 2> shoulder_pitch{}, shoulder_roll{}, elbow{};
};

// Where the hands ended up (world), to attach carried or pushed objects.
struct BodyAnchors {
  std::array<Eigen::Vector3f, 2> hands;
};

BodyAnchors add_humanoid(TriangleSoup& soup, const BodyPose& pose, const Appearance& look);

}  // namespace lrd::synth
