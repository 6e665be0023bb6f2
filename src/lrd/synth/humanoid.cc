#include "lrd/synth/humanoid.h"

#include <cmath>

namespace lrd::synth {
namespace {

using Eigen::AngleAxisf;
using Eigen::Isometry3f;
using Eigen::Matrix3f;
using Eigen::Vector3f;

Matrix3f rot_x(float a) {
  return AngleAxisf(a, Vector3f::UnitX()).toRotationMatrix();
}
Matrix3f rot_y(float a) {
  return AngleAxisf(a, Vector3f::UnitY()).toRotationMatrix();
}
Matrix3f rot_z(float a) {
  return AngleAxisf(a, Vector3f::UnitZ()).toRotationMatrix();
}

Isometry3f frame(const Vector3f& origin, const Matrix3f& R) {
  Isometry3f t = Isometry3f::Identity();
  t.translation() = origin;
  t.linear() = R;
  return t;
}

SurfaceStyle person_style(TextureId tex, float m) {
  SurfaceStyle s;
  s.texture = tex;
  s.metres_per_repeat = m;
  s.voc_class = voc::kPerson;
  s.label = MaskLabel::kPerson;
  return s;
}

}  // namespace

BodyAnchors add_humanoid(TriangleSoup& soup, const BodyPose& pose, const Appearance& look) {
  const float k = look.height / 1.75f;  // proportions of a 1.75 m adult
  const float g = look.girth;
  const SurfaceStyle shirt = person_style(look.shirt, 0.45f);
  const SurfaceStyle trousers = person_style(look.trousers, 0.35f);
  const SurfaceStyle skin = person_style(look.skin, 0.2f);
  const SurfaceStyle hair = person_style(look.hair, 0.15f);
  const SurfaceStyle shoes = person_style(look.shoes, 0.2f);
  const Matrix3f flip = rot_x(static_cast<float>(M_PI));  // prisms grow along +z; limbs hang along -z

  const Matrix3f R0 = pose.root.linear();
  const Vector3f pelvis = pose.root * Vector3f(0, 0, pose.pelvis_height * k);
  // Pelvis block.
  soup.add_prism(frame(pelvis - R0 * Vector3f(0, 0, 0.1f * k), R0), 0.12f * g * k, 0.17f * g * k,
                 0.12f * g * k, 0.17f * g * k, 0.16f * k, 8, trousers);

  // Legs.
  for (int s = 0; s < 2; ++s) {
    const float side = s == 0 ? 1.0f : -1.0f;  // left is +y
    const Vector3f hip = pelvis + R0 * Vector3f(0, side * 0.09f * g * k, -0.06f * k);
    const Matrix3f R_leg = R0 * rot_y(-pose.hip_pitch[s]) * rot_x(side * pose.hip_roll[s]);
    soup.add_prism(frame(hip, R_leg * flip), 0.085f * g * k, 0.085f * g * k, 0.06f * g * k, 0.06f * g * k,
                   0.44f * k, 8, trousers);
    const Vector3f knee = hip + R_leg * Vector3f(0, 0, -0.44f * k);
    const Matrix3f R_shin = R_leg * rot_y(pose.knee[s]);
    soup.add_prism(frame(knee, R_shin * flip), 0.06f * g * k, 0.06f * g * k, 0.045f * g * k, 0.045f * g * k,
                   0.41f * k, 8, trousers);
    const Vector3f ankle = knee + R_shin * Vector3f(0, 0, -0.41f * k);
    // Foot: stays roughly level with the shin's heading.
    // Feet stay near level: they follow half the shin's swing.
    const Matrix3f R_foot = R0 * rot_y(-0.5f * (pose.hip_pitch[s] - pose.knee[s]));
    Isometry3f foot = frame(ankle + R_foot * Vector3f(0.06f * k, 0, -0.04f * k), R_foot);
    soup.add_box(foot, Vector3f(0.26f * k, 0.1f * g * k, 0.07f * k), shoes);
  }

  // Torso, neck, head.
  const Matrix3f R_torso = R0 * rot_z(pose.torso_yaw) * rot_y(pose.torso_pitch) * rot_x(pose.torso_roll);
  soup.add_prism(frame(pelvis, R_torso), 0.12f * g * k, 0.17f * g * k, 0.13f * g * k, 0.2f * g * k, 0.52f * k,
                 10, shirt);
  const Vector3f neck = pelvis + R_torso * Vector3f(0, 0, 0.52f * k);
  const Matrix3f R_head = R_torso * rot_z(pose.head_yaw) * rot_y(pose.head_pitch);
  soup.add_prism(frame(neck, R_head), 0.05f * k, 0.05f * k, 0.05f * k, 0.05f * k, 0.07f * k, 6, skin);
  const Vector3f chin = neck + R_head * Vector3f(0.01f * k, 0, 0.06f * k);
  soup.add_prism(frame(chin, R_head), 0.09f * k, 0.075f * k, 0.1f * k, 0.085f * k, 0.15f * k, 10, skin);
  // Hair: a cap over the crown and the back of the head, so the head has a front and a back.
  soup.add_prism(frame(chin + R_head * Vector3f(-0.015f * k, 0, 0.13f * k), R_head), 0.105f * k, 0.09f * k,
                 0.06f * k, 0.05f * k, 0.11f * k, 10, hair);

  // Arms.
  BodyAnchors anchors;
  for (int s = 0; s < 2; ++s) {
    const float side = s == 0 ? 1.0f : -1.0f;
    const Vector3f shoulder = pelvis + R_torso * Vector3f(0, side * 0.22f * g * k, 0.47f * k);
    const Matrix3f R_arm =
        R_torso * rot_y(-pose.shoulder_pitch[s]) * rot_x(side * (pose.shoulder_roll[s] + 0.08f));
    soup.add_prism(frame(shoulder, R_arm * flip), 0.055f * g * k, 0.055f * g * k, 0.045f * g * k,
                   0.045f * g * k, 0.29f * k, 8, shirt);
    const Vector3f elbow = shoulder + R_arm * Vector3f(0, 0, -0.29f * k);
    const Matrix3f R_fore = R_arm * rot_y(-pose.elbow[s]);
    soup.add_prism(frame(elbow, R_fore * flip), 0.045f * g * k, 0.045f * g * k, 0.035f * g * k,
                   0.035f * g * k, 0.25f * k, 8, skin);
    const Vector3f wrist = elbow + R_fore * Vector3f(0, 0, -0.25f * k);
    soup.add_prism(frame(wrist, R_fore * flip), 0.03f * k, 0.045f * k, 0.025f * k, 0.04f * k, 0.09f * k, 6,
                   skin);
    anchors.hands[static_cast<std::size_t>(s)] = wrist + R_fore * Vector3f(0, 0, -0.07f * k);
  }
  return anchors;
}

}  // namespace lrd::synth
