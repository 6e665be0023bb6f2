// lrd::eval: association, rigid alignment, ATE statistics, RPE and the improvement rate, each against
// hand-computed values (the TUM-script agreement on random data is tests/python/test_eval_reference.py).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "lrd/eval/alignment.h"
#include "lrd/eval/association.h"
#include "lrd/eval/ate.h"
#include "lrd/eval/improvement.h"
#include "lrd/eval/rpe.h"
#include "lrd/eval/statistics.h"
#include "lrd/util/error.h"

namespace {

using lrd::io::StampedPose;
using lrd::io::Trajectory;

constexpr double kDeg = std::numbers::pi / 180.0;

StampedPose pose_at(double t, const Eigen::Matrix3d& r, const Eigen::Vector3d& p) {
  StampedPose s;
  s.timestamp = t;
  s.pose.linear() = r;
  s.pose.translation() = p;
  return s;
}

Eigen::Matrix3d rot_z(double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

Eigen::Isometry3d some_rigid_transform() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(4.0, -2.5, 0.75);
  return t;
}

TEST(EvalAssociation, GreedySmallestDifferenceFirst) {
  // Candidates: (a1,b0) 0.002, (a0,b0) 0.010, (a1,b1) 0.013. Greedy takes (a1,b0) and then has nothing
  // left for a0 or b1, although pairing (a0,b0),(a1,b1) would match both: associate.py's behaviour.
  const std::vector<double> first = {1.000, 1.012};
  const std::vector<double> second = {1.010, 1.025};
  const auto m = lrd::eval::associate(first, second, 0.02);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].first, 1u);
  EXPECT_EQ(m[0].second, 0u);
}

TEST(EvalAssociation, StrictWindowTiesAndOrder) {
  // |dt| == max_dt is rejected (strict <).
  EXPECT_TRUE(lrd::eval::associate(std::vector<double>{0.0}, std::vector<double>{0.5}, 0.5).empty());
  // Equal differences: the smaller first stamp wins, as sorting (diff, a, b) does.
  const auto tie = lrd::eval::associate(std::vector<double>{0.0, 0.5}, std::vector<double>{0.25}, 0.3);
  ASSERT_EQ(tie.size(), 1u);
  EXPECT_EQ(tie[0].first, 0u);
  // The result is ordered by first stamp, not by the order the pairs were taken in.
  const auto m =
      lrd::eval::associate(std::vector<double>{1.0, 2.0, 3.0}, std::vector<double>{1.015, 2.001, 2.99}, 0.02);
  ASSERT_EQ(m.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(m[k].first, k);
    EXPECT_EQ(m[k].second, k);
  }
}

TEST(EvalAlignment, RecoversRigidTransformAndAvoidsReflection) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix3Xd gt(3, 50);
  for (int k = 0; k < gt.cols(); ++k) gt.col(k) = Eigen::Vector3d(n(rng), n(rng), n(rng));
  const Eigen::Isometry3d t = some_rigid_transform();
  const Eigen::Matrix3Xd est = t.inverse() * gt;
  const Eigen::Isometry3d a = lrd::eval::align_rigid(est, gt);
  EXPECT_LE((a.matrix() - t.matrix()).cwiseAbs().maxCoeff(), 1e-12);

  // A mirrored estimate: the best proper rotation, never a reflection.
  Eigen::Matrix3Xd mirrored = gt;
  mirrored.row(0) *= -1.0;
  EXPECT_NEAR(lrd::eval::align_rigid(mirrored, gt).linear().determinant(), 1.0, 1e-12);
}

TEST(Ate, RigidlyTransformedGroundTruthGivesZero) {
  Trajectory gt, est;
  const Eigen::Isometry3d world = some_rigid_transform();
  for (int k = 0; k < 300; ++k) {
    const double t = 100.0 + k / 30.0;
    gt.push_back(pose_at(t, rot_z(0.1 * t), {std::sin(t), std::cos(0.7 * t), 0.2 * t}));
    StampedPose e = gt.back();
    e.timestamp += 0.005;  // within max_dt
    e.pose = world * e.pose;
    est.push_back(e);
  }
  const lrd::eval::AteResult ate = lrd::eval::compute_ate(gt, est);
  EXPECT_EQ(ate.stats.count, 300u);
  EXPECT_LE(ate.stats.rmse, 1e-9);
  EXPECT_LE(ate.stats.max, 1e-9);
  EXPECT_LE((ate.alignment.matrix() - world.inverse().matrix()).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Ate, HandComputedOffsetPattern) {
  // Ground truth in the z = 0 plane, symmetric about the origin; the estimate is offset along z by
  // d with sum(d) = sum(d x) = sum(d y) = 0, so the best alignment is the identity and the errors
  // are |d| = {0, .1, .1, .5, .5, .6, .6, .2, .2}. The estimate is also moved rigidly.
  const std::vector<Eigen::Vector2d> xy = {{0, 0}, {1, 0},  {-1, 0}, {0, 1}, {0, -1},
                                           {2, 0}, {-2, 0}, {0, 2},  {0, -2}};
  const std::vector<double> d = {0.0, 0.1, 0.1, -0.5, -0.5, 0.6, 0.6, -0.2, -0.2};
  const Eigen::Isometry3d world = some_rigid_transform();
  Trajectory gt, est;
  for (std::size_t k = 0; k < xy.size(); ++k) {
    const double t = static_cast<double>(k);
    gt.push_back(pose_at(t, Eigen::Matrix3d::Identity(), {xy[k].x(), xy[k].y(), 0.0}));
    est.push_back(
        pose_at(t, Eigen::Matrix3d::Identity(), world * Eigen::Vector3d(xy[k].x(), xy[k].y(), d[k])));
  }
  const lrd::eval::ErrorStats s = lrd::eval::compute_ate(gt, est).stats;
  const double mean = 2.8 / 9.0, mean_sq = 1.32 / 9.0;
  EXPECT_EQ(s.count, 9u);
  EXPECT_NEAR(s.rmse, std::sqrt(mean_sq), 1e-12);
  EXPECT_NEAR(s.mean, mean, 1e-12);
  EXPECT_NEAR(s.median, 0.2, 1e-12);
  EXPECT_NEAR(s.std_dev, std::sqrt(mean_sq - mean * mean), 1e-12);
  EXPECT_NEAR(s.min, 0.0, 1e-12);
  EXPECT_NEAR(s.max, 0.6, 1e-12);
}

TEST(Ate, NoOverlapThrows) {
  Trajectory gt, est;
  for (int k = 0; k < 10; ++k) {
    gt.push_back(pose_at(k, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()));
    est.push_back(pose_at(k + 0.5, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()));
  }
  EXPECT_THROW((void)lrd::eval::compute_ate(gt, est), lrd::Error);
}

TEST(EvalStatistics, NumpyDefinitions) {
  const std::vector<double> e = {10.0, 1.0, 4.0, 2.0};
  const lrd::eval::ErrorStats s = lrd::eval::compute_stats(e);
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.median, 3.0);  // mean of the two middle values
  EXPECT_DOUBLE_EQ(s.mean, 4.25);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(121.0 / 4.0));
  EXPECT_DOUBLE_EQ(s.std_dev,
                   std::sqrt((5.75 * 5.75 + 3.25 * 3.25 + 0.25 * 0.25 + 2.25 * 2.25) / 4.0));  // ddof 0
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 10.0);
  EXPECT_DOUBLE_EQ(lrd::eval::median(std::vector<double>{3.0, 1.0, 2.0}), 2.0);
}

TEST(Rpe, FindClosestIndexIsTheScriptsBinarySearch) {
  const std::vector<double> l = {0, 1, 2, 3, 4};
  EXPECT_EQ(lrd::eval::find_closest_index(l, 2.2), 2u);
  EXPECT_EQ(lrd::eval::find_closest_index(l, -7.0), 0u);
  EXPECT_EQ(lrd::eval::find_closest_index(l, 99.0), 4u);
  // Halfway ties go to whichever neighbour the search visits first: 2 for both.
  EXPECT_EQ(lrd::eval::find_closest_index(l, 2.5), 2u);
  EXPECT_EQ(lrd::eval::find_closest_index(l, 1.5), 2u);
}

TEST(Rpe, ConstantVelocityDriftGivesHandComputedRates) {
  // Ground truth turns about z at 10 deg/s in place; the estimate turns at 12 deg/s and moves at
  // 0.05 m/s. With delta = 1 s, E = inv(inv(P_j) P_i) (inv(Q_j) Q_i) has |t| = 0.05 m and a 2 deg
  // rotation for every pair.
  Trajectory gt, est;
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.1 * k;
    gt.push_back(pose_at(t, rot_z(10.0 * kDeg * t), Eigen::Vector3d::Zero()));
    est.push_back(pose_at(t, rot_z(12.0 * kDeg * t), Eigen::Vector3d(0.05 * t, 0.0, 0.0)));
  }
  const lrd::eval::RpeResult rpe = lrd::eval::compute_rpe(gt, est, 1.0);
  // i = 0..89 pair with j = i + 10; i = 90 reaches the last pose and later ones find only it.
  ASSERT_EQ(rpe.pairs.size(), 90u);
  EXPECT_EQ(rpe.pairs.front().est_j, 10u);
  EXPECT_EQ(rpe.pairs.back().est_i, 89u);
  EXPECT_NEAR(rpe.trans.rmse, 0.05, 1e-12);
  EXPECT_NEAR(rpe.trans.mean, 0.05, 1e-12);
  EXPECT_NEAR(rpe.trans.max, 0.05, 1e-12);
  EXPECT_NEAR(rpe.trans.std_dev, 0.0, 1e-12);
  EXPECT_NEAR(rpe.rot.rmse, 2.0, 1e-6);
  EXPECT_NEAR(rpe.rot.median, 2.0, 1e-6);
  EXPECT_NEAR(rpe.rot.min, 2.0, 1e-6);
}

TEST(Rpe, SkipsPairsWithoutNearbyGroundTruth) {
  // Ground truth at 10 Hz with no poses in (3.0, 5.0); the estimate at all stamps, 0.03 s later.
  // The limit is 2 x 0.1 s, so estimated stamps 3.23 .. 4.73 (k = 32..47) have no ground truth.
  Trajectory gt, est;
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.1 * k;
    if (k <= 30 || k >= 50) gt.push_back(pose_at(t, Eigen::Matrix3d::Identity(), Eigen::Vector3d(t, 0, 0)));
    est.push_back(pose_at(t + 0.03, Eigen::Matrix3d::Identity(), Eigen::Vector3d(t + 0.03, 0, 0)));
  }
  const lrd::eval::RpeResult rpe = lrd::eval::compute_rpe(gt, est, 1.0);
  // Of the 90 pairs (i, i + 10), those with i or i + 10 in 32..47 go (i = 22..47): 90 - 26 = 64.
  EXPECT_EQ(rpe.pairs.size(), 64u);
  for (const lrd::eval::RpePair& p : rpe.pairs) {
    EXPECT_LE(std::abs(gt[p.gt_i].timestamp - est[p.est_i].timestamp), 0.2);
    EXPECT_LE(std::abs(gt[p.gt_j].timestamp - est[p.est_j].timestamp), 0.2);
  }
  // Next to the gap the matched ground truth is 0.17 s off: (2.13 -> 3.13) meets (2.1 -> 3.0), 0.1 m.
  EXPECT_NEAR(rpe.pairs[21].trans, 0.1, 1e-9);
}

TEST(Rpe, TooFewPairsThrows) {
  Trajectory gt, est;
  for (double t : {0.0, 0.5, 1.0}) {
    gt.push_back(pose_at(t, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()));
    est.push_back(pose_at(t, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()));
  }
  EXPECT_THROW((void)lrd::eval::compute_rpe(gt, est, 1.0), lrd::Error);
}

TEST(EvalImprovement, PaperEquation12) {
  EXPECT_DOUBLE_EQ(lrd::eval::improvement_percent(0.2, 0.15), 25.0);
  EXPECT_DOUBLE_EQ(lrd::eval::improvement_percent(0.1, 0.2), -100.0);
  EXPECT_TRUE(std::isnan(lrd::eval::improvement_percent(0.0, 0.1)));
  lrd::eval::ErrorStats base, ours;
  base.rmse = 4.0;
  ours.rmse = 1.0;
  base.max = 2.0;
  ours.max = 3.0;
  base.mean = base.median = base.std_dev = base.min = 1.0;
  const lrd::eval::ErrorStats eta = lrd::eval::improvement_percent(base, ours);
  EXPECT_DOUBLE_EQ(eta.rmse, 75.0);
  EXPECT_DOUBLE_EQ(eta.max, -50.0);
  EXPECT_DOUBLE_EQ(eta.mean, 100.0);
}

}  // namespace
