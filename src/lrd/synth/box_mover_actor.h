#pragma once
// A person who carries a box from one resting place to another and puts it down, walks away and
// waits, then carries it back (Bonn RGB-D Dynamic's moving_nonobstructing_box and
// moving_obstructing_box): an object no person-class network labels, at rest for seconds between
// moves. Its mask label follows its motion: kMovedObject while lifted, carried or put down,
// static while it rests on the floor.
#include <string>
#include <vector>

#include "lrd/synth/actor.h"
#include "lrd/synth/humanoid.h"

namespace lrd::synth {

struct BoxMoveParams {
  Eigen::Vector2f home{0.0f, 0.0f};    // floor point where the person waits between moves
  Eigen::Vector2f spot_a{0.0f, 0.0f};  // the box's two resting places (floor, under its centre)
  Eigen::Vector2f spot_b{0.0f, 0.0f};
  Eigen::Vector3f box_size{0.42f, 0.5f, 0.36f};
  float speed = 0.8f;  // m/s while walking
  double wait = 3.0;   // s at home after each move
  double start = 0.0;  // s into the cycle at t = 0
  float phase = 0.0f;  // of the head's motion
};

class BoxMoverActor : public Actor {
 public:
  BoxMoverActor(BoxMoveParams params, Appearance look, const TextureLibrary& tex, std::string name);
  void add_geometry(double t, TriangleSoup& soup) const override;
  [[nodiscard]] std::string describe() const override;
  // Both moves (a to b, then b to a) with the walks, turns and waits around them.
  [[nodiscard]] double period() const { return period_; }
  static constexpr double kTurnSeconds = 0.6, kLiftSeconds = 1.2;
  // Where the box is at time t, and whether it is moving then (kMovedObject) or at rest.
  struct BoxState {
    Eigen::Vector3f centre;
    float yaw = 0.0f;
    bool moving = false;
  };
  [[nodiscard]] BoxState box_at(double t) const;

 private:
  enum class StepKind { kWalk, kTurn, kLift, kLower, kWait };
  struct Step {
    StepKind kind = StepKind::kWait;
    Eigen::Vector2f from{0.0f, 0.0f}, to{0.0f, 0.0f};
    float yaw_from = 0.0f, yaw_to = 0.0f;
    double duration = 0.0;
    bool carrying = false;
    int box_at_spot = 0;  // where the box rests during the step when not carried: 0 = a, 1 = b
  };
  // Where the person is within the cycle.
  struct Moment {
    const Step* step = nullptr;
    double into = 0.0;  // s into the step
  };
  void add_move(const Eigen::Vector2f& from, const Eigen::Vector2f& to, int from_spot);
  void add_walk(const Eigen::Vector2f& to, bool carrying, int box_spot);
  void add_turn(float yaw, bool carrying, int box_spot);
  [[nodiscard]] Moment moment_at(double t) const;
  [[nodiscard]] float carry_height() const;

  BoxMoveParams params_;
  Appearance look_;
  const TextureLibrary& tex_;
  std::string name_;
  std::vector<Step> steps_;
  double period_ = 0.0;
  // The script's builder state: where the person stands and faces.
  Eigen::Vector2f at_{0.0f, 0.0f};
  float yaw_ = 0.0f;
};

}  // namespace lrd::synth
