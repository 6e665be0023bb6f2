#include "lrd/optim/ba_problem.h"

#include <ceres/rotation.h>

#include <cmath>

#include "lrd/data/frame.h"

namespace lrd::optim {

PoseBlock to_block(const Eigen::Isometry3d& T) {
  PoseBlock b{};
  const Eigen::AngleAxisd aa(T.rotation());
  const Eigen::Vector3d w = aa.angle() * aa.axis();
  b = {w.x(), w.y(), w.z(), T.translation().x(), T.translation().y(), T.translation().z()};
  return b;
}

Eigen::Isometry3d from_block(const PoseBlock& b) {
  const Eigen::Vector3d w(b[0], b[1], b[2]);
  const double angle = w.norm();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (angle > 0) T.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  T.translation() = Eigen::Vector3d(b[3], b[4], b[5]);
  return T;
}

Observation make_observation(std::size_t kf, std::size_t point, const data::Frame& f, std::size_t keypoint) {
  const cv::KeyPoint& kp = f.undistorted()[keypoint];
  return {kf,
          point,
          keypoint,
          kp.pt.x,
          kp.pt.y,
          f.u_right(keypoint),
          f.inv_level_sigma2()[static_cast<std::size_t>(kp.octave)]};
}

namespace {

// Residual sqrt(1/sigma^2) * (observed - projected), 2 entries (mono) or 3 (with depth: the
// disparity u - u_right against bf / z, divided by the disparity sigma); the same model as
// PinholeCamera::reprojection_chi2.
template <int N>
struct ReprojectionError {
  Intrinsics k;
  double u, v, ur, sqrt_info;
  template <class T>
  bool operator()(const T* pose, const T* point, T* residual) const {
    T p[3];
    ceres::AngleAxisRotatePoint(pose, point, p);
    p[0] += pose[3];
    p[1] += pose[4];
    p[2] += pose[5];
    const T iz = T(1.0) / p[2];
    const T pu = k.fx * p[0] * iz + k.cx;
    residual[0] = (u - pu) * sqrt_info;
    residual[1] = (v - (k.fy * p[1] * iz + k.cy)) * sqrt_info;
    if constexpr (N == 3) residual[2] = ((u - ur) - k.bf * iz) * (sqrt_info / k.disparity_sigma);
    return true;
  }
};

class AbortCallback : public ceres::IterationCallback {
 public:
  explicit AbortCallback(const std::atomic<bool>* abort) : abort_(abort) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    return abort_ != nullptr && abort_->load() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
  }

 private:
  const std::atomic<bool>* abort_;
};

}  // namespace

// chi2 of one observation (unweighted by the kernel) and whether the point is in front.
double chi2(const Intrinsics& k, const PoseBlock& pose, const PointBlock& point, const Observation& o,
            bool& front) {
  double p[3];
  ceres::AngleAxisRotatePoint(pose.data(), point.data(), p);
  p[0] += pose[3], p[1] += pose[4], p[2] += pose[5];
  front = p[2] > 0.0;
  if (!front) return 1e12;
  const double iz = 1.0 / p[2];
  const double pu = k.fx * p[0] * iz + k.cx, pv = k.fy * p[1] * iz + k.cy;
  double e2 = (o.u - pu) * (o.u - pu) + (o.v - pv) * (o.v - pv);
  if (o.ur >= 0) {
    const double ed = ((o.u - o.ur) - k.bf * iz) / k.disparity_sigma;
    e2 += ed * ed;
  }
  return e2 * o.inv_sigma2;
}

double rms(const Intrinsics& k, const std::vector<PoseBlock>& poses, const std::vector<PointBlock>& points,
           const std::vector<Observation>& obs) {
  double sum = 0.0;
  int n = 0;
  for (const Observation& o : obs) {
    if (o.outlier) continue;
    bool front;
    const double c = chi2(k, poses[o.kf], points[o.point], o, front);
    if (!front) continue;
    sum += c;
    ++n;
  }
  return n > 0 ? std::sqrt(sum / n) : 0.0;
}

bool solve(const Intrinsics& k, std::vector<PoseBlock>& poses, std::size_t n_free,
           std::vector<PointBlock>& points, const std::vector<Observation>& obs, const BaSolveOptions& opts) {
  const bool robust = opts.robust;
  ceres::Problem::Options popts;
  popts.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(popts);
  auto* ordering = new ceres::ParameterBlockOrdering;
  for (const Observation& o : obs) {
    if (o.outlier) continue;
    ceres::LossFunction* loss = nullptr;
    ceres::CostFunction* cost;
    const double sqrt_info = std::sqrt(o.inv_sigma2);
    if (o.ur >= 0) {
      cost = new ceres::AutoDiffCostFunction<ReprojectionError<3>, 3, 6, 3>(
          new ReprojectionError<3>{k, o.u, o.v, o.ur, sqrt_info});
      if (robust) loss = new ceres::HuberLoss(std::sqrt(opts.chi2_stereo));
    } else {
      cost = new ceres::AutoDiffCostFunction<ReprojectionError<2>, 2, 6, 3>(
          new ReprojectionError<2>{k, o.u, o.v, -1.0, sqrt_info});
      if (robust) loss = new ceres::HuberLoss(std::sqrt(opts.chi2_mono));
    }
    problem.AddResidualBlock(cost, loss, poses[o.kf].data(), points[o.point].data());
  }
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!problem.HasParameterBlock(poses[i].data())) continue;
    ordering->AddElementToGroup(poses[i].data(), 1);
    if (i >= n_free) problem.SetParameterBlockConstant(poses[i].data());
  }
  for (PointBlock& p : points)
    if (problem.HasParameterBlock(p.data())) ordering->AddElementToGroup(p.data(), 0);
  if (problem.NumResidualBlocks() == 0) {
    delete ordering;
    return true;
  }

  ceres::Solver::Options options;
  options.linear_solver_type = opts.linear_solver;
  options.linear_solver_ordering.reset(ordering);
  options.max_num_iterations = opts.iterations;
  options.num_threads = 1;  // deterministic, and tracking has the other core
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  AbortCallback callback(opts.abort);
  options.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary.termination_type != ceres::USER_FAILURE;
}

int classify_outliers(const Intrinsics& k, const std::vector<PoseBlock>& poses,
                      const std::vector<PointBlock>& points, std::vector<Observation>& obs, double chi2_mono,
                      double chi2_stereo) {
  int n = 0;
  for (Observation& o : obs) {
    bool front;
    const double c = chi2(k, poses[o.kf], points[o.point], o, front);
    o.outlier = !front || c > (o.ur >= 0 ? chi2_stereo : chi2_mono);
    n += o.outlier ? 1 : 0;
  }
  return n;
}

}  // namespace lrd::optim
