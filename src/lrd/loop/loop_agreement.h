#pragma once
// Whether a loop's correction agrees with structure the map already has (the divergence hunt,
// bench/results/divergence.md). A true loop links two parts of the map that share no structure yet:
// drift kept tracking from recognising the old place. When the loop keyframe already observes
// points of the current keyframe's neighbourhood, the map holds the relative pose of the two sides
// already, and a correction that moves the neighbourhood's points away from where the loop keyframe
// sees them is not a loop but a wrong transform (seen on a camera retracing its path: a "loop" to a
// keyframe nine keyframes back, 22 RANSAC inliers, a 0.45 m move that put those points 280 px off).
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

namespace lrd::map {
class KeyFrame;
}

namespace lrd::loop {

struct LoopAgreement {
  std::size_t shared = 0;         // observations by the loop keyframe of the neighbourhood's points
  double median_before_px = 0.0;  // their reprojection error in the loop keyframe now
  double median_after_px = 0.0;   // ... with the neighbourhood moved by the correction
  // Enough shared observations, and the correction makes them disagree: at least min_px off and
  // three times as far as before.
  [[nodiscard]] bool contradicts(std::size_t min_shared = 20, double min_px = 10.0) const {
    return shared >= min_shared && median_after_px > min_px && median_after_px > 3.0 * median_before_px;
  }
};

// `motion`: the rigid world motion the correction applies to the neighbourhood and its points
// (T_cw_corrected^-1 * T_cw of the current keyframe). The loop keyframe must not belong to the
// neighbourhood. Call under Map::mutex().
[[nodiscard]] LoopAgreement measure_loop_agreement(const std::vector<map::KeyFrame*>& neighbourhood,
                                                   const map::KeyFrame& loop_keyframe,
                                                   const Eigen::Isometry3d& motion);

}  // namespace lrd::loop
