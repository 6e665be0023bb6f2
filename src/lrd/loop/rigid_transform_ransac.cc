#include "lrd/loop/rigid_transform_ransac.h"

#include <Eigen/Geometry>
#include <random>

namespace lrd::loop {

namespace {

bool reprojects(const camera::PinholeCamera& cam, const Eigen::Vector3d& p, const Eigen::Vector2d& px,
                double sigma2, double chi2) {
  if (p.z() <= 0.0) return false;
  const double u = cam.fx * p.x() / p.z() + cam.cx, v = cam.fy * p.y() / p.z() + cam.cy;
  const double e2 = (u - px.x()) * (u - px.x()) + (v - px.y()) * (v - px.y());
  return e2 < chi2 * sigma2;
}

int count_inliers(const std::vector<PointCorrespondence>& m, const camera::PinholeCamera& cam,
                  const Eigen::Isometry3d& T_12, double chi2, std::vector<bool>& inlier) {
  const Eigen::Isometry3d T_21 = T_12.inverse();
  int n = 0;
  inlier.assign(m.size(), false);
  for (std::size_t i = 0; i < m.size(); ++i) {
    inlier[i] = reprojects(cam, T_12 * m[i].p2, m[i].px1, m[i].sigma2_1, chi2) &&
                reprojects(cam, T_21 * m[i].p1, m[i].px2, m[i].sigma2_2, chi2);
    n += inlier[i] ? 1 : 0;
  }
  return n;
}

// A portable index draw: std::uniform_int_distribution differs between standard libraries.
std::size_t draw(std::mt19937_64& rng, std::size_t n) {
  return static_cast<std::size_t>((rng() >> 11) * 0x1.0p-53 * static_cast<double>(n)) % n;
}

}  // namespace

Eigen::Isometry3d fit_rigid(const std::vector<Eigen::Vector3d>& from,
                            const std::vector<Eigen::Vector3d>& to) {
  Eigen::Matrix3Xd a(3, static_cast<Eigen::Index>(from.size())), b(3, static_cast<Eigen::Index>(to.size()));
  for (std::size_t i = 0; i < from.size(); ++i) {
    a.col(static_cast<Eigen::Index>(i)) = from[i];
    b.col(static_cast<Eigen::Index>(i)) = to[i];
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.matrix() = Eigen::umeyama(a, b, false);
  return T;
}

RigidRansacResult estimate_rigid_ransac(const std::vector<PointCorrespondence>& m,
                                        const camera::PinholeCamera& cam, const RigidRansacParams& params) {
  RigidRansacResult best;
  if (m.size() < 3 || static_cast<int>(m.size()) < params.min_inliers) return best;
  std::mt19937_64 rng(params.seed);
  std::vector<bool> inlier;
  for (int it = 0; it < params.iterations; ++it) {
    std::size_t idx[3];
    idx[0] = draw(rng, m.size());
    do idx[1] = draw(rng, m.size());
    while (idx[1] == idx[0]);
    do idx[2] = draw(rng, m.size());
    while (idx[2] == idx[0] || idx[2] == idx[1]);
    const Eigen::Vector3d d1 = m[idx[1]].p2 - m[idx[0]].p2, d2 = m[idx[2]].p2 - m[idx[0]].p2;
    if (d1.cross(d2).norm() < 1e-6) continue;  // collinear sample
    const Eigen::Isometry3d T =
        fit_rigid({m[idx[0]].p2, m[idx[1]].p2, m[idx[2]].p2}, {m[idx[0]].p1, m[idx[1]].p1, m[idx[2]].p1});
    const int n = count_inliers(m, cam, T, params.chi2, inlier);
    if (n > best.inliers) {
      best.inliers = n;
      best.T_12 = T;
      best.inlier = inlier;
    }
  }
  if (best.inliers < params.min_inliers) return RigidRansacResult{};
  // Refit on the inliers, and keep the refit if it explains at least as many.
  std::vector<Eigen::Vector3d> from, to;
  for (std::size_t i = 0; i < m.size(); ++i)
    if (best.inlier[i]) from.push_back(m[i].p2), to.push_back(m[i].p1);
  const Eigen::Isometry3d refit = fit_rigid(from, to);
  const int n = count_inliers(m, cam, refit, params.chi2, inlier);
  if (n >= best.inliers) {
    best.T_12 = refit;
    best.inliers = n;
    best.inlier = inlier;
  }
  best.ok = true;
  return best;
}

}  // namespace lrd::loop
