#pragma once
// Rotation-consistency check (ORB-SLAM2): true matches between two views share roughly the same
// change of keypoint orientation, so matches outside the three most populated bins of the angle
// difference histogram are dropped.
#include <array>
#include <cstddef>
#include <vector>

namespace lrd::match {

class RotationHistogram {
 public:
  static constexpr int kBins = 30;
  // Records match `index` with keypoint angles (degrees) in the two views.
  void add(float angle_a, float angle_b, std::size_t index);
  // Indices of matches to drop (not in the three largest bins; a bin smaller than 10 % of the
  // largest does not count).
  [[nodiscard]] std::vector<std::size_t> rejected() const;

 private:
  std::array<std::vector<std::size_t>, kBins> bins_;
};

}  // namespace lrd::match
