#pragma once
// A person who walks straight at the camera, stops close enough to fill most of the view for a
// moment, turns round, walks back and waits (the harder content's walking_close,
// docs/synthetic-benchmark.md): the frames where a person hides nearly everything static, and a
// mask that must follow them to the image border.
#include <string>

#include "lrd/synth/actor.h"
#include "lrd/synth/humanoid.h"

namespace lrd::synth {

struct ApproachParams {
  Eigen::Vector2f far{0.0f, 0.0f};   // floor point where they wait
  Eigen::Vector2f near{0.0f, 0.0f};  // floor point where they stand, facing the camera
  float speed = 0.8f;                // m/s while walking
  double hold = 1.2;                 // s standing at `near`
  double wait = 4.0;                 // s standing at `far`
  double start = 0.0;                // s into the cycle at t = 0
  float phase = 0.0f;                // of the head's motion
};

class ApproachingActor : public Actor {
 public:
  ApproachingActor(ApproachParams params, Appearance look, std::string name);
  void add_geometry(double t, TriangleSoup& soup) const override;
  [[nodiscard]] std::string describe() const override;
  static constexpr double kTurnSeconds = 0.8;
  // One walk there, hold, turn, walk back, turn and wait.
  [[nodiscard]] double period() const;

 private:
  ApproachParams params_;
  Appearance look_;
  std::string name_;
};

}  // namespace lrd::synth
