#pragma once
// A person walking a closed path with swinging arms and legs, slowing and speeding up, turning
// along the path; optionally pushing a chair or carrying a box (objects moved by external force,
// which a person-class network does not label).
#include <string>

#include "lrd/synth/actor.h"
#include "lrd/synth/humanoid.h"
#include "lrd/synth/path2d.h"

namespace lrd::synth {

enum class CarriedProp { kNone, kPushedChair, kCarriedBox };

struct WalkingParams {
  std::vector<Eigen::Vector2f> waypoints;
  float speed = 1.0f;            // mean m/s
  float speed_variation = 0.5f;  // 0..0.9: relative amplitude of the speed's slow oscillation
  float start = 0.0f;            // arc length at t = 0
  float phase = 0.0f;            // of head and speed oscillations
  CarriedProp prop = CarriedProp::kNone;
};

// The walking body on `root` (floor, +x forward) at stride phase `phi` (2 pi per stride), its
// swings scaled by `amp` (0: standing), head turning with time `tf`; the arms hold `prop`.
[[nodiscard]] BodyPose walking_body(const Eigen::Isometry3f& root, float phi, float amp, float tf,
                                    float phase, CarriedProp prop);

// An unladen person `s` m into a walk of `length` m (s clamped to it): the stride phase follows the
// distance, the swings grow over the first steps and die down over the last, standing at either end.
[[nodiscard]] BodyPose walk_leg_body(const Eigen::Isometry3f& root, float s, float length,
                                     const Appearance& look, float tf, float phase);

class WalkingActor : public Actor {
 public:
  WalkingActor(WalkingParams params, Appearance look, const TextureLibrary& tex, std::string name);
  void add_geometry(double t, TriangleSoup& soup) const override;
  [[nodiscard]] std::string describe() const override;
  // Where the person stands on the floor at time t (a following camera's target).
  [[nodiscard]] Eigen::Vector2f floor_position(double t) const;

 private:
  // How far along the path they are at time t (seconds from the sequence start).
  [[nodiscard]] float arc_length(float t) const;
  WalkingParams params_;
  Appearance look_;
  const TextureLibrary& tex_;
  ClosedPath path_;
  std::string name_;
};

}  // namespace lrd::synth
