#pragma once
// The bundle-adjustment problem shared by local BA (local_bundle_adjuster.h) and global BA
// (global_bundle_adjuster.h): keyframe poses and map points as Ceres parameter blocks,
// reprojection residuals weighted by the keypoint's pyramid level (3 entries with depth: the
// disparity bf / z, weighted by the camera's disparity_sigma), optional Huber kernel, and an
// abort flag checked each iteration.
#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <cstddef>
#include <vector>

namespace lrd::data {
class Frame;
}

namespace lrd::optim {

// Pose block: angle-axis rotation (3) then translation (3) of T_cw.
using PoseBlock = std::array<double, 6>;
using PointBlock = std::array<double, 3>;

PoseBlock to_block(const Eigen::Isometry3d& T);
Eigen::Isometry3d from_block(const PoseBlock& b);

struct Intrinsics {
  double fx, fy, cx, cy, bf;
  double disparity_sigma;  // PinholeCamera::disparity_sigma
};

struct Observation {
  std::size_t kf;     // index into the pose blocks
  std::size_t point;  // index into the point blocks
  std::size_t keypoint;
  double u, v, ur, inv_sigma2;
  bool outlier = false;
};

// The observation of keypoint `keypoint` of frame `f` (a keyframe's features) for the pose block
// `kf` and the point block `point`.
Observation make_observation(std::size_t kf, std::size_t point, const data::Frame& f, std::size_t keypoint);

struct BaSolveOptions {
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  bool robust = true;
  int iterations = 10;
  ceres::LinearSolverType linear_solver = ceres::DENSE_SCHUR;
  const std::atomic<bool>* abort = nullptr;
};

// chi2 of one observation (unweighted by the kernel) and whether the point is in front.
double chi2(const Intrinsics& k, const PoseBlock& pose, const PointBlock& point, const Observation& o,
            bool& front);
// Weighted reprojection RMS over the inlier observations.
double rms(const Intrinsics& k, const std::vector<PoseBlock>& poses, const std::vector<PointBlock>& points,
           const std::vector<Observation>& obs);
// Solves in place; poses with index >= n_free stay fixed. False when aborted.
bool solve(const Intrinsics& k, std::vector<PoseBlock>& poses, std::size_t n_free,
           std::vector<PointBlock>& points, const std::vector<Observation>& obs,
           const BaSolveOptions& options);
// Marks observations beyond the chi-square thresholds (or behind the camera) as outliers.
int classify_outliers(const Intrinsics& k, const std::vector<PoseBlock>& poses,
                      const std::vector<PointBlock>& points, std::vector<Observation>& obs, double chi2_mono,
                      double chi2_stereo);

}  // namespace lrd::optim
