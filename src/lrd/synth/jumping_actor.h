#pragma once
// A person who jumps on the spot in sets, in step with the others of the same preset (Bonn RGB-D
// Dynamic's synchronous sequences): every dynamic point moves up and down together, so no single
// person's motion stands out against the others'.
#include <string>

#include "lrd/synth/actor.h"
#include "lrd/synth/humanoid.h"

namespace lrd::synth {

struct JumpParams {
  Eigen::Vector2f spot{0.0f, 0.0f};  // floor point they jump on
  float yaw = 0.0f;                  // direction they face
  double period = 1.0;               // s per jump
  int jumps_per_set = 5;
  double rest = 2.5;    // s standing between sets
  float height = 0.2f;  // m the feet leave the floor at the top
  double start = 0.0;   // s into the cycle at t = 0 (equal for people in step)
  float phase = 0.0f;   // of the head's motion
};

class JumpingActor : public Actor {
 public:
  JumpingActor(JumpParams params, Appearance look, std::string name);
  void add_geometry(double t, TriangleSoup& soup) const override;
  [[nodiscard]] std::string describe() const override;
  // One set of jumps and the rest after it.
  [[nodiscard]] double period() const { return params_.jumps_per_set * params_.period + params_.rest; }
  // How far the feet are off the floor at time t.
  [[nodiscard]] float lift_at(double t) const;

 private:
  // Where in its jump the person is at time t, 0..1 from the crouch to standing again; -1 while
  // they rest between sets.
  [[nodiscard]] double jump_phase(double t) const;
  JumpParams params_;
  Appearance look_;
  std::string name_;
};

}  // namespace lrd::synth
