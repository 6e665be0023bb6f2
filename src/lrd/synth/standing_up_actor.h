#pragma once
// A seated person who, after sitting for a while, stands up and walks out of the view (the harder
// content's sitting_standup, docs/synthetic-benchmark.md): static for long enough to be mapped as
// background by the keyframes of that time, then moving, so that a stale keyframe's view of them
// disagrees with the present.
#include <string>
#include <vector>

#include "lrd/synth/actor.h"
#include "lrd/synth/seated_actor.h"

namespace lrd::synth {

class StandingUpActor : public Actor {
 public:
  // Sits as `seated` until `stand_at` seconds, rises over kRiseSeconds, then walks the floor
  // polyline `exit` (from beside the seat) at `speed` m/s and stands still at its end.
  StandingUpActor(SeatedActor seated, double stand_at, std::vector<Eigen::Vector2f> exit, float speed,
                  std::string name);
  void add_geometry(double t, TriangleSoup& soup) const override;
  [[nodiscard]] std::string describe() const override;
  static constexpr double kRiseSeconds = 1.5;

 private:
  // Floor position and heading (yaw) at arc length s along the exit, clamped to its end.
  void exit_at(float s, Eigen::Vector2f& position, float& yaw) const;
  [[nodiscard]] BodyPose rising_pose(double t) const;
  SeatedActor seated_;
  double stand_at_;
  std::vector<Eigen::Vector2f> exit_;
  float speed_;
  float exit_length_ = 0.0f;
  std::string name_;
};

}  // namespace lrd::synth
