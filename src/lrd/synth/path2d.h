#pragma once
// A closed path on the floor (Catmull-Rom through waypoints), sampled by arc length, that walking
// actors follow.
#include <Eigen/Core>
#include <vector>

namespace lrd::synth {

class ClosedPath {
 public:
  explicit ClosedPath(const std::vector<Eigen::Vector2f>& waypoints, int samples_per_segment = 64);

  [[nodiscard]] float length() const { return cumulative_.back(); }
  // Position and unit heading at arc length s (wraps around).
  void at(float s, Eigen::Vector2f& position, Eigen::Vector2f& heading) const;

 private:
  [[nodiscard]] Eigen::Vector2f point_at(float s) const;
  std::vector<Eigen::Vector2f> points_;
  std::vector<float> cumulative_;
};

}  // namespace lrd::synth
