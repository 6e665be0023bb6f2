#include "lrd/optim/local_bundle_adjuster.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <vector>

#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/map/map_point.h"

namespace lrd::optim {
namespace {

// Pose block: angle-axis rotation (3) then translation (3) of T_cw.
using PoseBlock = std::array<double, 6>;
using PointBlock = std::array<double, 3>;

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

struct Intrinsics {
  double fx, fy, cx, cy, bf;
};

// Residual sqrt(1/sigma^2) * (observed - projected), 2 entries (mono) or 3 (with u_right).
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
    if constexpr (N == 3) residual[2] = (ur - (pu - k.bf * iz)) * sqrt_info;
    return true;
  }
};

struct Observation {
  std::size_t kf;     // index into the pose blocks (local then fixed)
  std::size_t point;  // index into the point blocks
  std::size_t keypoint;
  double u, v, ur, inv_sigma2;
  bool outlier = false;
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

// chi2 of one observation (unweighted by the kernel) and whether the point is in front.
double chi2(const Intrinsics& k, const PoseBlock& pose, const PointBlock& point, const Observation& o, bool& front) {
  double p[3];
  ceres::AngleAxisRotatePoint(pose.data(), point.data(), p);
  p[0] += pose[3], p[1] += pose[4], p[2] += pose[5];
  front = p[2] > 0.0;
  if (!front) return 1e12;
  const double iz = 1.0 / p[2];
  const double pu = k.fx * p[0] * iz + k.cx, pv = k.fy * p[1] * iz + k.cy;
  double e2 = (o.u - pu) * (o.u - pu) + (o.v - pv) * (o.v - pv);
  if (o.ur >= 0) e2 += (o.ur - (pu - k.bf * iz)) * (o.ur - (pu - k.bf * iz));
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

bool solve(const Intrinsics& k, std::vector<PoseBlock>& poses, std::size_t n_local, std::vector<PointBlock>& points,
           const std::vector<Observation>& obs, const LocalBundleAdjustmentParams& params, bool robust, int iterations,
           const std::atomic<bool>* abort) {
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
      if (robust) loss = new ceres::HuberLoss(std::sqrt(params.chi2_stereo));
    } else {
      cost = new ceres::AutoDiffCostFunction<ReprojectionError<2>, 2, 6, 3>(
          new ReprojectionError<2>{k, o.u, o.v, -1.0, sqrt_info});
      if (robust) loss = new ceres::HuberLoss(std::sqrt(params.chi2_mono));
    }
    problem.AddResidualBlock(cost, loss, poses[o.kf].data(), points[o.point].data());
  }
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!problem.HasParameterBlock(poses[i].data())) continue;
    ordering->AddElementToGroup(poses[i].data(), 1);
    if (i >= n_local) problem.SetParameterBlockConstant(poses[i].data());
  }
  for (PointBlock& p : points)
    if (problem.HasParameterBlock(p.data())) ordering->AddElementToGroup(p.data(), 0);
  if (problem.NumResidualBlocks() == 0) {
    delete ordering;
    return true;
  }

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.linear_solver_ordering.reset(ordering);
  options.max_num_iterations = iterations;
  options.num_threads = 1;  // deterministic, and tracking has the other core
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  AbortCallback callback(abort);
  options.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary.termination_type != ceres::USER_FAILURE;
}

}  // namespace

LocalBundleAdjustmentStats local_bundle_adjustment(map::KeyFrame* keyframe, map::Map& map,
                                                   const std::atomic<bool>* abort,
                                                   const LocalBundleAdjustmentParams& params) {
  LocalBundleAdjustmentStats stats;
  std::vector<map::KeyFrame*> kfs;  // local ones first, then fixed ones
  std::vector<map::MapPoint*> mps;
  std::vector<PoseBlock> poses;
  std::vector<PointBlock> points;
  std::vector<Observation> obs;
  std::size_t n_local = 0;
  Intrinsics k{};
  {
    std::lock_guard lock(map.mutex());
    if (keyframe->is_bad()) return stats;
    const camera::PinholeCamera& cam = keyframe->features().camera();
    k = {cam.fx, cam.fy, cam.cx, cam.cy, cam.bf};
    const std::uint64_t tag = keyframe->id();
    kfs.push_back(keyframe);
    keyframe->local_ba_for_kf = tag;
    const auto neighbours = params.max_local_keyframes > 0
                                ? keyframe->best_covisibles(static_cast<std::size_t>(params.max_local_keyframes))
                                : keyframe->ordered_covisibles();
    for (map::KeyFrame* kf : neighbours) {
      if (kf->is_bad() || kf->local_ba_for_kf == tag) continue;
      kf->local_ba_for_kf = tag;
      kfs.push_back(kf);
    }
    n_local = kfs.size();
    for (std::size_t i = 0; i < n_local; ++i) {
      for (map::MapPoint* mp : kfs[i]->map_points()) {
        if (mp == nullptr || mp->is_bad() || mp->local_ba_for_kf == tag) continue;
        mp->local_ba_for_kf = tag;
        mps.push_back(mp);
      }
    }
    // Deterministic layout whatever the neighbour order: points by id.
    std::sort(mps.begin(), mps.end(), map::ById{});
    for (map::MapPoint* mp : mps)
      for (const auto& [kf, idx] : mp->observations())
        if (!kf->is_bad() && kf->local_ba_for_kf != tag && kf->fixed_ba_for_kf != tag) {
          kf->fixed_ba_for_kf = tag;
          kfs.push_back(kf);
        }
    std::sort(kfs.begin() + static_cast<long>(n_local), kfs.end(), map::ById{});
    for (map::KeyFrame* kf : kfs) poses.push_back(to_block(kf->T_cw()));
    std::map<const map::KeyFrame*, std::size_t> index;
    for (std::size_t i = 0; i < kfs.size(); ++i) index[kfs[i]] = i;
    for (std::size_t p = 0; p < mps.size(); ++p) {
      const Eigen::Vector3d& x = mps[p]->position();
      points.push_back({x.x(), x.y(), x.z()});
      for (const auto& [kf, idx] : mps[p]->observations()) {
        const auto it = index.find(kf);
        if (it == index.end()) continue;
        const data::Frame& f = kf->features();
        const cv::KeyPoint& kp = f.undistorted()[idx];
        obs.push_back({it->second, p, idx, kp.pt.x, kp.pt.y, f.u_right(idx),
                       f.inv_level_sigma2()[static_cast<std::size_t>(kp.octave)]});
      }
    }
  }
  stats.local_keyframes = static_cast<int>(n_local);
  stats.fixed_keyframes = static_cast<int>(kfs.size() - n_local);
  stats.points = static_cast<int>(mps.size());
  stats.observations = static_cast<int>(obs.size());
  if (obs.empty()) return stats;
  // Keyframe 0 defines the world frame: never move it (swap it to the end of the local range,
  // which makes it the first fixed one).
  for (std::size_t i = 0; i < n_local; ++i) {
    if (kfs[i]->id() != 0) continue;
    const std::size_t last = n_local - 1;
    std::swap(kfs[i], kfs[last]);
    std::swap(poses[i], poses[last]);
    for (Observation& o : obs) {
      if (o.kf == i) o.kf = last;
      else if (o.kf == last) o.kf = i;
    }
    --n_local;
    break;
  }
  stats.initial_rms_px = rms(k, poses, points, obs);

  if (!solve(k, poses, n_local, points, obs, params, true, params.first_iterations, abort)) stats.aborted = true;
  if (!stats.aborted) {
    for (Observation& o : obs) {
      bool front;
      const double c = chi2(k, poses[o.kf], points[o.point], o, front);
      o.outlier = !front || c > (o.ur >= 0 ? params.chi2_stereo : params.chi2_mono);
    }
    if (!solve(k, poses, n_local, points, obs, params, false, params.second_iterations, abort)) stats.aborted = true;
  }
  // Final classification on the result (ORB-SLAM2 also erases these after an aborted round).
  for (Observation& o : obs) {
    bool front;
    const double c = chi2(k, poses[o.kf], points[o.point], o, front);
    o.outlier = !front || c > (o.ur >= 0 ? params.chi2_stereo : params.chi2_mono);
  }
  stats.final_rms_px = rms(k, poses, points, obs);

  std::lock_guard lock(map.mutex());
  for (const Observation& o : obs) {
    if (!o.outlier) continue;
    ++stats.outliers;
    map::KeyFrame* kf = kfs[o.kf];
    map::MapPoint* mp = mps[o.point];
    if (kf->map_point(o.keypoint) == mp) kf->erase_map_point(o.keypoint);
    mp->erase_observation(kf);
  }
  for (std::size_t i = 0; i < n_local; ++i)
    if (!kfs[i]->is_bad()) kfs[i]->set_pose(from_block(poses[i]));
  for (std::size_t p = 0; p < mps.size(); ++p) {
    if (mps[p]->is_bad()) continue;
    mps[p]->set_position(Eigen::Vector3d(points[p][0], points[p][1], points[p][2]));
    mps[p]->update_normal_and_depth();
  }
  return stats;
}

}  // namespace lrd::optim
