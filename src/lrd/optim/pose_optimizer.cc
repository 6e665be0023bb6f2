#include "lrd/optim/pose_optimizer.h"

#include <cmath>
#include <utility>

#include "lrd/data/frame.h"
#include "lrd/geometry/se3.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"

namespace lrd::optim {
namespace {

using geometry::Vector6d;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct Residual {
  // (du, dv, d_disparity / disparity_sigma); third unused for mono. PinholeCamera::reprojection_chi2's model.
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 3, 6> J = Eigen::Matrix<double, 3, 6>::Zero();  // d e / d xi (left perturbation)
  bool stereo = false;
  bool valid = false;  // point in front of the camera
  [[nodiscard]] double chi2(double inv_sigma2) const {
    return inv_sigma2 * (stereo ? e.squaredNorm() : e.head<2>().squaredNorm());
  }
};

Residual residual(const camera::PinholeCamera& cam, const PoseObservation& o, const Eigen::Isometry3d& T_cw,
                  bool with_jacobian) {
  Residual r;
  const Eigen::Vector3d p = T_cw * o.point_w;
  if (p.z() <= 1e-6) return r;
  r.valid = true;
  r.stereo = o.u_right >= 0.0;
  const double iz = 1.0 / p.z(), iz2 = iz * iz;
  const double u = cam.fx * p.x() * iz + cam.cx, v = cam.fy * p.y() * iz + cam.cy;
  r.e.x() = o.pixel.x() - u;
  r.e.y() = o.pixel.y() - v;
  const double inv_ds = 1.0 / cam.disparity_sigma;
  if (r.stereo) r.e.z() = ((o.pixel.x() - o.u_right) - cam.bf * iz) * inv_ds;
  if (!with_jacobian) return r;
  // d(prediction)/d(p_c), then d(p_c)/d(xi) = [-[p_c]x, I]; the residual is obs - prediction.
  Eigen::Matrix<double, 3, 3> dproj;
  dproj << cam.fx * iz, 0.0, -cam.fx * p.x() * iz2, 0.0, cam.fy * iz, -cam.fy * p.y() * iz2, 0.0, 0.0,
      -cam.bf * iz2 * inv_ds;
  Eigen::Matrix<double, 3, 6> dp;
  dp.leftCols<3>() = -geometry::skew(p);
  dp.rightCols<3>().setIdentity();
  r.J = -dproj * dp;
  if (!r.stereo) r.J.row(2).setZero();
  return r;
}

// Huber weight for a residual of squared (whitened) norm chi2 and threshold delta^2.
double huber_weight(double chi2, double delta2) {
  return chi2 <= delta2 ? 1.0 : std::sqrt(delta2 / chi2);
}

// Robust cost of the current inliers at T and, with H and g given, the Gauss-Newton system there
// (Huber-weighted J^T J and J^T e). One pass serves both: an accepted step's cost pass is the
// next iteration's linearisation, with the same numbers as two separate passes.
double linearize(const camera::PinholeCamera& cam, const std::vector<PoseObservation>& obs,
                 const std::vector<bool>& out, const Eigen::Isometry3d& T, bool robust,
                 const PoseOptimizerParams& p, Matrix6d* H, Vector6d* g) {
  if (H != nullptr) H->setZero(), g->setZero();
  double c = 0.0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (out[i]) continue;
    const Residual r = residual(cam, obs[i], T, H != nullptr);
    if (!r.valid) {
      c += 1e6;
      continue;
    }
    const double chi2 = r.chi2(obs[i].inv_sigma2);
    const double d2 = r.stereo ? p.chi2_stereo : p.chi2_mono;
    c += robust && chi2 > d2 ? 2.0 * std::sqrt(d2 * chi2) - d2 : chi2;
    if (H == nullptr) continue;
    const double w = obs[i].inv_sigma2 * (robust ? huber_weight(chi2, d2) : 1.0);
    H->noalias() += w * r.J.transpose() * r.J;
    g->noalias() += w * r.J.transpose() * r.e;
  }
  return c;
}

// Levenberg-Marquardt on the left perturbation T <- exp(xi) T over the inliers, at most
// params.iterations steps. Stops once a step would move the pose by less than kConverged (squared
// norm of xi: 1e-6 rad and 1e-6 m, far below what any test of ours can see): the next steps only
// chase rounding, and at the optimum every attempt fails until lambda has grown 8 times.
void refine(const camera::PinholeCamera& cam, const std::vector<PoseObservation>& obs,
            const std::vector<bool>& outlier, bool robust, const PoseOptimizerParams& params,
            Eigen::Isometry3d& T) {
  constexpr double kConverged = 1e-12;
  double lambda = 1e-4;
  Matrix6d H, H_candidate;
  Vector6d g, g_candidate;
  double current = linearize(cam, obs, outlier, T, robust, params, &H, &g);
  for (int it = 0; it < params.iterations; ++it) {
    // The last iteration's accepted step needs no system: its cost alone decides.
    const bool last = it + 1 == params.iterations;
    bool improved = false;
    for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
      Matrix6d A = H;
      A.diagonal() += lambda * H.diagonal().cwiseMax(1e-9);
      const Vector6d xi = A.ldlt().solve(-g);
      if (!xi.allFinite() || xi.squaredNorm() < kConverged) return;
      const Eigen::Isometry3d candidate = geometry::orthonormalized(geometry::se3_exp(xi) * T);
      const double c = linearize(cam, obs, outlier, candidate, robust, params, last ? nullptr : &H_candidate,
                                 last ? nullptr : &g_candidate);
      if (c < current) {
        T = candidate;
        current = c;
        if (!last) H = H_candidate, g = g_candidate;
        lambda = std::max(lambda * 0.3, 1e-9);
        improved = true;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) return;
  }
}

}  // namespace

PoseOptimizationResult optimize_pose(const camera::PinholeCamera& cam,
                                     const std::vector<PoseObservation>& obs,
                                     const Eigen::Isometry3d& T_cw_initial,
                                     const PoseOptimizerParams& params) {
  PoseOptimizationResult result;
  result.T_cw = T_cw_initial;
  result.outlier.assign(obs.size(), false);
  if (obs.size() < 3) {
    result.inliers = static_cast<int>(obs.size());
    return result;
  }
  std::vector<bool> previous_outliers;
  Eigen::Isometry3d T = T_cw_initial;
  for (int round = 0; round < params.rounds; ++round) {
    const bool robust = round < params.robust_rounds;
    // The same kernel over the same inliers as the round before has the same optimum.
    if (round > 0 && robust == (round - 1 < params.robust_rounds) && result.outlier == previous_outliers)
      continue;
    previous_outliers = result.outlier;
    refine(cam, obs, result.outlier, robust, params, T);
    // Re-classify every observation (outliers may come back) against the chi-square thresholds.
    int inliers = 0;
    for (std::size_t i = 0; i < obs.size(); ++i) {
      const Residual r = residual(cam, obs[i], T, false);
      const double chi2 = r.valid ? r.chi2(obs[i].inv_sigma2) : 1e12;
      result.outlier[i] = chi2 > (r.stereo ? params.chi2_stereo : params.chi2_mono);
      inliers += !result.outlier[i];
    }
    result.inliers = inliers;
    if (inliers < params.min_inliers) break;
  }
  result.T_cw = geometry::orthonormalized(T);
  return result;
}

PoseOptimizationResult optimize_frame_pose(const data::Frame& frame,
                                           const std::vector<map::MapPoint*>& matches,
                                           const Eigen::Isometry3d& T_cw, const PoseOptimizerParams& params) {
  std::vector<PoseObservation> obs;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (matches[i] == nullptr) continue;
    const cv::KeyPoint& kp = frame.undistorted()[i];
    obs.push_back({matches[i]->position(), Eigen::Vector2d(kp.pt.x, kp.pt.y), frame.u_right(i),
                   frame.inv_level_sigma2()[static_cast<std::size_t>(kp.octave)]});
    index.push_back(i);
  }
  if (obs.size() < 3) return {T_cw, {}, 0};
  PoseOptimizationResult result = optimize_pose(frame.camera(), obs, T_cw, params);
  std::vector<bool> per_keypoint(matches.size(), false);
  for (std::size_t k = 0; k < index.size(); ++k) per_keypoint[index[k]] = result.outlier[k];
  result.outlier = std::move(per_keypoint);
  return result;
}

}  // namespace lrd::optim
