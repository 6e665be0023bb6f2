#pragma once
// Motion-only bundle adjustment: the camera pose that best explains matched map points, with a
// Huber kernel and chi-square outlier rejection in rounds, as ORB-SLAM2's PoseOptimization
// (4 rounds x 10 iterations; 5.991 for monocular and 7.815 for stereo-like observations, the
// 95 % chi-square quantiles for 2 and 3 degrees of freedom). Levenberg-Marquardt on SE(3) with
// analytic Jacobians: a 6-parameter problem needs no general solver.
#include <Eigen/Geometry>
#include <vector>

#include "lrd/camera/pinhole_camera.h"

namespace lrd::data {
class Frame;
}
namespace lrd::map {
class MapPoint;
}

namespace lrd::optim {

struct PoseObservation {
  Eigen::Vector3d point_w;  // map point in the world frame
  Eigen::Vector2d pixel;    // undistorted keypoint
  double u_right = -1.0;    // RGB-D virtual right coordinate u - bf / depth; < 0: monocular
  double inv_sigma2 = 1.0;  // 1 / sigma^2 of the keypoint's pyramid level
};

struct PoseOptimizerParams {
  int rounds = 4;
  int iterations = 10;
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  int robust_rounds = 2;  // the Huber kernel is dropped after this many rounds (ORB-SLAM2)
  int min_inliers = 10;   // stop re-classifying below this
};

struct PoseOptimizationResult {
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();  // world-to-camera
  std::vector<bool> outlier;                               // per observation
  int inliers = 0;
};

[[nodiscard]] PoseOptimizationResult optimize_pose(const camera::PinholeCamera& camera,
                                                   const std::vector<PoseObservation>& observations,
                                                   const Eigen::Isometry3d& T_cw_initial,
                                                   const PoseOptimizerParams& params = {});

// The same for a frame's keypoints: `matches` holds one slot per keypoint (null: unmatched), each
// observed at its undistorted position, virtual right coordinate and pyramid level. The result's
// `outlier` is per keypoint (false where unmatched); empty, with `T_cw` and no inliers, when fewer
// than three keypoints are matched.
[[nodiscard]] PoseOptimizationResult optimize_frame_pose(const data::Frame& frame,
                                                         const std::vector<map::MapPoint*>& matches,
                                                         const Eigen::Isometry3d& T_cw,
                                                         const PoseOptimizerParams& params = {});

}  // namespace lrd::optim
