#pragma once
// Two people who throw a balloon to each other and catch it (Bonn RGB-D Dynamic's balloon
// sequences): a light, slow, textured sphere of no class a segmentation network knows, so that
// only the geometry check can find it. Mask labels: the people kPerson, the balloon kBalloon.
#include <string>

#include "lrd/synth/actor.h"
#include "lrd/synth/humanoid.h"

namespace lrd::synth {

struct BalloonParams {
  Eigen::Vector2f first{0.0f, 0.0f};  // floor points where the two people stand, facing each other
  Eigen::Vector2f second{0.0f, 0.0f};
  double flight = 1.6;   // s from one pair of hands to the other
  double hold = 0.7;     // s the catcher holds it before throwing it back
  float apex = 0.6f;     // m the arc rises above the hands
  float drift = 0.25f;   // m the arc bows sideways (a balloon floats, it does not fly straight)
  float radius = 0.16f;  // m
  double start = 0.0;    // s into the cycle at t = 0
  float phase = 0.0f;
};

class BalloonActor : public Actor {
 public:
  BalloonActor(BalloonParams params, Appearance first_look, Appearance second_look, const TextureLibrary& tex,
               std::string name);
  void add_geometry(double t, TriangleSoup& soup) const override;
  [[nodiscard]] std::string describe() const override;
  // One throw there and one back.
  [[nodiscard]] double period() const { return 2.0 * (params_.flight + params_.hold); }
  // The balloon's centre at time t (world).
  [[nodiscard]] Eigen::Vector3f balloon_at(double t) const;

 private:
  // Where a person's held balloon is: in front of their chest.
  [[nodiscard]] Eigen::Vector3f held_at(int person) const;
  // The person's pose: arms up while holding, about to catch or throwing; down otherwise.
  [[nodiscard]] BodyPose person_pose(int person, double t) const;

  BalloonParams params_;
  Appearance looks_[2];
  TextureId balloon_texture_;
  std::string name_;
};

}  // namespace lrd::synth
