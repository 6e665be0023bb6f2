#pragma once
// A person sitting on a chair who shifts, leans, turns the torso and head, and gestures.
#include <string>

#include "lrd/synth/actor.h"
#include "lrd/synth/humanoid.h"

namespace lrd::synth {

class SeatedActor : public Actor {
 public:
  // `seat`: chair pose (origin on the floor, +x the way the person faces); `phase` varies the motion.
  SeatedActor(const Eigen::Isometry3f& seat, Appearance look, float phase, float liveliness,
              std::string name);
  void add_geometry(double t, TriangleSoup& soup) const override;
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] BodyPose pose_at(double t) const;
  [[nodiscard]] const Appearance& look() const { return look_; }
  [[nodiscard]] const Eigen::Isometry3f& seat() const { return seat_; }

 private:
  Eigen::Isometry3f seat_;
  Appearance look_;
  float phase_;
  float liveliness_;
  std::string name_;
};

}  // namespace lrd::synth
