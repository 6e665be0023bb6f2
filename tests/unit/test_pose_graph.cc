// Pose-graph optimization: a drifting ring closed by one loop edge is pulled back to ground truth,
// a consistent graph stays put, fixed nodes stay fixed, bad input is an lrd::Error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "error_of.h"
#include "lrd/geometry/se3.h"
#include "lrd/optim/pose_graph_optimizer.h"

using lrd::geometry::se3_exp;
using lrd::geometry::Vector6d;
using lrd::optim::optimize_pose_graph;
using lrd::optim::PoseGraphEdge;
using lrd::optim::PoseGraphNode;
using lrd::optim::PoseGraphParams;

namespace {

Vector6d twist(double wx, double wy, double wz, double vx, double vy, double vz) {
  Vector6d xi;
  xi << wx, wy, wz, vx, vy, vz;
  return xi;
}

// Ground truth T_cw of n cameras on a circle of radius 3 m, each looking along the tangent, with
// some height and tilt so that the problem is not planar.
std::vector<Eigen::Isometry3d> ring(int n) {
  std::vector<Eigen::Isometry3d> T_cw;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * i / n;
    Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
    T_wc.linear() = (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(0.1 * std::sin(2.0 * a), Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    T_wc.translation() = Eigen::Vector3d(3.0 * std::cos(a), 3.0 * std::sin(a), 0.3 * std::sin(3.0 * a));
    T_cw.push_back(T_wc.inverse());
  }
  return T_cw;
}

Eigen::Isometry3d relative(const Eigen::Isometry3d& T_cw_to, const Eigen::Isometry3d& T_cw_from) {
  return T_cw_to * T_cw_from.inverse();
}

Eigen::Vector3d center(const Eigen::Isometry3d& T_cw) {
  return T_cw.inverse().translation();
}

// (rotation angle, translation norm) of an edge's residual T_to_from^-1 * T_cw[to] * T_cw[from]^-1.
std::pair<double, double> residual(const PoseGraphEdge& e,
                                   const std::map<std::uint64_t, Eigen::Isometry3d>& T_cw) {
  const Eigen::Isometry3d E = e.T_to_from.inverse() * T_cw.at(e.to) * T_cw.at(e.from).inverse();
  return {Eigen::AngleAxisd(E.linear()).angle(), E.translation().norm()};
}

double max_center_error(const std::map<std::uint64_t, Eigen::Isometry3d>& T_cw,
                        const std::vector<Eigen::Isometry3d>& truth) {
  double m = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i)
    m = std::max(m, (center(T_cw.at(i)) - center(truth[i])).norm());
  return m;
}

double max_pose_difference(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff();
}

// A ring whose odometry edges carry a consistent bias, nodes initialised by dead reckoning along
// them, closed by one exact loop edge from the last node to the first (which is fixed).
struct DriftingRing {
  std::vector<Eigen::Isometry3d> truth;
  std::vector<PoseGraphNode> nodes;
  std::vector<PoseGraphEdge> edges;  // odometry 0->1, ..., (n-2)->(n-1), then the loop edge
};

DriftingRing drifting_ring(int n) {
  DriftingRing r;
  r.truth = ring(n);
  const Eigen::Isometry3d bias = se3_exp(twist(0.002, 0.002, 0.001, 0.005, 0.005, 0.02));
  r.nodes.push_back({0, r.truth[0], true});
  for (int i = 0; i + 1 < n; ++i) {
    const auto from = static_cast<std::uint64_t>(i);
    const Eigen::Isometry3d meas = bias * relative(r.truth[from + 1], r.truth[from]);
    r.edges.push_back({from, from + 1, meas});
    r.nodes.push_back({from + 1, meas * r.nodes.back().T_cw, false});
  }
  const auto last = static_cast<std::uint64_t>(n - 1);
  r.edges.push_back({last, 0, relative(r.truth[0], r.truth[last])});
  return r;
}

// The cost of the graph's edges at the poses `T_cw` (node i at T_cw[i]).
double cost_at(const std::vector<Eigen::Isometry3d>& T_cw, const std::vector<PoseGraphEdge>& edges) {
  std::vector<PoseGraphNode> nodes;
  for (std::uint64_t i = 0; i < T_cw.size(); ++i) nodes.push_back({i, T_cw[i], i == 0});
  PoseGraphParams params;
  params.iterations = 0;
  return optimize_pose_graph(nodes, edges, params).initial_cost;
}

std::map<std::uint64_t, Eigen::Isometry3d> as_map(const std::vector<PoseGraphNode>& nodes) {
  std::map<std::uint64_t, Eigen::Isometry3d> m;
  for (const PoseGraphNode& n : nodes) m[n.id] = n.T_cw;
  return m;
}

}  // namespace

TEST(PoseGraph, LoopEdgeRemovesAccumulatedDrift) {
  const DriftingRing r = drifting_ring(40);
  const auto initial = as_map(r.nodes);
  const double error_before = max_center_error(initial, r.truth);
  const auto [loop_rot_before, loop_trans_before] = residual(r.edges.back(), initial);
  ASSERT_GT(error_before, 0.9);  // the drift is real: about a metre at the far end of the ring

  const auto result = optimize_pose_graph(r.nodes, r.edges);
  const double error_after = max_center_error(result.T_cw, r.truth);
  EXPECT_LT(error_after, 0.3 * error_before);
  // Not zero: biased odometry bends the whole ring, which one loop edge cannot observe.
  EXPECT_LT(error_after, 0.2);  // measured 0.159 m
  EXPECT_LT(result.final_cost, 0.01 * result.initial_cost);
  EXPECT_LE(result.final_cost, cost_at(r.truth, r.edges));  // a minimum: no worse than the truth
  EXPECT_GT(result.iterations, 0);

  // With equal weights the loop's inconsistency is shared out evenly: the loop edge keeps a small
  // part of it, no more than an odometry edge.
  const auto [loop_rot, loop_trans] = residual(r.edges.back(), result.T_cw);
  const double loop_before = std::hypot(loop_rot_before, loop_trans_before);
  const double loop_after = std::hypot(loop_rot, loop_trans);
  double max_odometry = 0.0;
  for (std::size_t i = 0; i + 1 < r.edges.size(); ++i) {
    const auto [rot, trans] = residual(r.edges[i], result.T_cw);
    max_odometry = std::max(max_odometry, std::hypot(rot, trans));
  }
  EXPECT_LT(loop_after, 0.05 * loop_before);
  EXPECT_LT(loop_after, 1.5 * max_odometry);
}

TEST(PoseGraph, HeavyLoopEdgeIsSatisfied) {
  DriftingRing r = drifting_ring(40);
  r.edges.back().weight = 1e6;  // a trusted loop measurement: its residual must vanish
  const auto result = optimize_pose_graph(r.nodes, r.edges);
  const auto [rot, trans] = residual(r.edges.back(), result.T_cw);
  EXPECT_LT(rot, 1e-6);  // measured 8e-9 rad, 3e-9 m
  EXPECT_LT(trans, 1e-6);
  EXPECT_LT(max_center_error(result.T_cw, r.truth), 0.2);  // measured 0.153 m
}

TEST(PoseGraph, ConsistentGraphStaysPut) {
  const std::vector<Eigen::Isometry3d> truth = ring(30);
  std::vector<PoseGraphNode> nodes;
  std::vector<PoseGraphEdge> edges;
  for (std::uint64_t i = 0; i < truth.size(); ++i) nodes.push_back({i, truth[i], i == 0});
  // Odometry, a loop, and covisibility-like chords: every measurement exact.
  for (std::uint64_t i = 0; i < truth.size(); ++i)
    for (std::uint64_t step : {1, 2, 7}) {
      const std::uint64_t j = (i + step) % truth.size();
      edges.push_back({i, j, relative(truth[j], truth[i])});
    }
  const auto result = optimize_pose_graph(nodes, edges);
  EXPECT_LT(result.initial_cost, 1e-20);
  EXPECT_LT(result.final_cost, 1e-20);
  for (std::uint64_t i = 0; i < truth.size(); ++i)
    EXPECT_LT(max_pose_difference(result.T_cw.at(i), truth[i]), 1e-9) << "node " << i;
}

TEST(PoseGraph, FixedNodesDoNotMove) {
  DriftingRing r = drifting_ring(40);
  r.nodes[13].fixed = true;  // anchored at its drifted estimate, which the loop would move
  r.nodes[27].fixed = true;
  const auto result = optimize_pose_graph(r.nodes, r.edges);
  for (std::size_t i : {0, 13, 27})
    EXPECT_EQ(max_pose_difference(result.T_cw.at(i), lrd::geometry::orthonormalized(r.nodes[i].T_cw)), 0.0)
        << "node " << i;
  // ... while the free ones did move, to where the reported poses give the reported cost.
  EXPECT_GT(max_pose_difference(result.T_cw.at(39), r.nodes[39].T_cw), 0.05);
  EXPECT_LT(result.final_cost, 0.1 * result.initial_cost);
  std::vector<Eigen::Isometry3d> T_cw;
  for (const auto& [id, T] : result.T_cw) T_cw.push_back(T);
  EXPECT_NEAR(cost_at(T_cw, r.edges), result.final_cost, 1e-9 * result.final_cost);
}

TEST(PoseGraph, CostIsTheDocumentedWeightedResidual) {
  // 0.5 * weight * (rotation_weight * |angle_axis(R_E)|^2 + translation_weight * |t_E|^2) with
  // E = T_to_from^-1 * T_cw[to] * T_cw[from]^-1.
  const Eigen::Isometry3d T_from = se3_exp(twist(0.2, -0.1, 0.3, 0.5, -1.0, 2.0));
  const Eigen::Isometry3d T_to = se3_exp(twist(-0.3, 0.4, 0.1, 1.5, 0.2, -0.7));
  const Eigen::Isometry3d meas = se3_exp(twist(0.05, 0.6, -0.2, 0.3, 0.3, 0.1));
  const Eigen::Isometry3d E = meas.inverse() * T_to * T_from.inverse();
  const double angle2 = std::pow(Eigen::AngleAxisd(E.linear()).angle(), 2);
  const double trans2 = E.translation().squaredNorm();
  ASSERT_GT(angle2, 0.01);
  ASSERT_GT(trans2, 0.01);
  PoseGraphParams params;
  params.iterations = 0;
  params.rotation_weight = 3.0;
  params.translation_weight = 0.25;
  const std::vector<PoseGraphNode> nodes{{7, T_from, true}, {3, T_to, false}};
  const auto result = optimize_pose_graph(nodes, {{7, 3, meas, 2.0}}, params);
  EXPECT_NEAR(result.initial_cost, 0.5 * 2.0 * (3.0 * angle2 + 0.25 * trans2), 1e-12);
}

TEST(PoseGraph, NodesInNoEdgeAreReturnedUnchanged) {
  DriftingRing r = drifting_ring(10);
  const Eigen::Isometry3d lone = se3_exp(twist(0.3, -0.2, 0.1, 1.0, 2.0, 3.0));
  r.nodes.push_back({100, lone, false});
  const auto result = optimize_pose_graph(r.nodes, r.edges);
  ASSERT_EQ(result.T_cw.size(), 11u);
  EXPECT_LT(max_pose_difference(result.T_cw.at(100), lone), 1e-15);
}

TEST(PoseGraph, EdgesBetweenFixedNodesOnlyAreCostedButMoveNothing) {
  const Eigen::Isometry3d T = se3_exp(twist(0.0, 0.0, 0.0, 1.0, 0.0, 0.0));
  const auto result = optimize_pose_graph({{0, Eigen::Isometry3d::Identity(), true}, {1, T, true}},
                                          {{0, 1, Eigen::Isometry3d::Identity()}});
  EXPECT_NEAR(result.initial_cost, 0.5, 1e-15);
  EXPECT_NEAR(result.final_cost, 0.5, 1e-15);
  EXPECT_EQ(result.iterations, 0);
  EXPECT_EQ(max_pose_difference(result.T_cw.at(1), T), 0.0);
}

TEST(PoseGraph, ResultsAreOrthonormalAndRepeatable) {
  const DriftingRing r = drifting_ring(40);
  const auto a = optimize_pose_graph(r.nodes, r.edges);
  const auto b = optimize_pose_graph(r.nodes, r.edges);
  for (const auto& [id, T] : a.T_cw) {
    EXPECT_LT((T.linear() * T.linear().transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12) << id;
    EXPECT_EQ(max_pose_difference(T, b.T_cw.at(id)), 0.0) << id;
  }
  EXPECT_EQ(a.final_cost, b.final_cost);
}

TEST(PoseGraph, ZeroIterationsReportsTheInitialCost) {
  const DriftingRing r = drifting_ring(10);
  PoseGraphParams params;
  params.iterations = 0;
  const auto result = optimize_pose_graph(r.nodes, r.edges, params);
  EXPECT_GT(result.initial_cost, 0.0);
  EXPECT_EQ(result.final_cost, result.initial_cost);
  EXPECT_EQ(result.iterations, 0);
  for (const PoseGraphNode& n : r.nodes) EXPECT_LT(max_pose_difference(result.T_cw.at(n.id), n.T_cw), 1e-12);
}

TEST(PoseGraph, RandomGraphConverges) {
  // An essential graph's shape: 100 nodes, odometry, covisibility chords to near neighbours and a
  // few long loop edges, noisy measurements, a noisy initial estimate. The optimum explains the
  // measurements to their noise level.
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  auto perturbation = [&](double rot, double trans) {
    return se3_exp(twist(rot * noise(rng), rot * noise(rng), rot * noise(rng), trans * noise(rng),
                         trans * noise(rng), trans * noise(rng)));
  };
  const std::vector<Eigen::Isometry3d> truth = ring(100);
  std::vector<PoseGraphNode> nodes;
  for (std::uint64_t i = 0; i < truth.size(); ++i)
    nodes.push_back({i, i == 0 ? truth[i] : perturbation(0.05, 0.2) * truth[i], i == 0});
  std::vector<PoseGraphEdge> edges;
  const std::uint64_t n = truth.size();
  std::uniform_int_distribution<std::uint64_t> pick(0, n - 1), near(2, 12);
  auto add_edge = [&](std::uint64_t a, std::uint64_t b) {
    edges.push_back({a, b, perturbation(0.001, 0.003) * relative(truth[b], truth[a])});
  };
  for (std::uint64_t i = 0; i + 1 < n; ++i) add_edge(i, i + 1);
  while (edges.size() < 595) {
    const std::uint64_t a = pick(rng);
    add_edge(a, (a + near(rng)) % n);
  }
  while (edges.size() < 600) {
    const std::uint64_t a = pick(rng), b = pick(rng);
    if (a != b) add_edge(a, b);
  }
  const auto result = optimize_pose_graph(nodes, edges);
  const double error_after = max_center_error(result.T_cw, truth);
  EXPECT_LT(error_after, 0.01);  // measured 0.0049 m
  EXPECT_GT(max_center_error(as_map(nodes), truth), 50.0 * error_after);
  EXPECT_LT(result.final_cost, 1e-3 * result.initial_cost);
  EXPECT_LE(result.final_cost, cost_at(truth, edges));
}

TEST(PoseGraph, BadInputIsAnError) {
  const DriftingRing r = drifting_ring(5);
  using lrd::test::error_of;
  {
    auto edges = r.edges;
    edges.push_back({2, 99, Eigen::Isometry3d::Identity()});
    EXPECT_EQ(error_of([&] { (void)optimize_pose_graph(r.nodes, edges); }),
              "pose graph: edge 5 (2 -> 99) refers to unknown node 99");
    edges.back() = {98, 2, Eigen::Isometry3d::Identity()};
    EXPECT_EQ(error_of([&] { (void)optimize_pose_graph(r.nodes, edges); }),
              "pose graph: edge 5 (98 -> 2) refers to unknown node 98");
    edges.back() = {2, 2, Eigen::Isometry3d::Identity()};
    EXPECT_NE(error_of([&] { (void)optimize_pose_graph(r.nodes, edges); }).find("itself"), std::string::npos);
    edges.back() = {1, 2, Eigen::Isometry3d::Identity(), 0.0};
    EXPECT_NE(error_of([&] { (void)optimize_pose_graph(r.nodes, edges); }).find("weight"), std::string::npos);
  }
  {
    auto nodes = r.nodes;
    nodes[0].fixed = false;
    EXPECT_NE(error_of([&] { (void)optimize_pose_graph(nodes, r.edges); }).find("no fixed node"),
              std::string::npos);
    nodes[0].fixed = true;
    nodes.push_back(nodes[3]);
    EXPECT_EQ(error_of([&] { (void)optimize_pose_graph(nodes, r.edges); }),
              "pose graph: duplicate node id 3");
    nodes.pop_back();
    nodes[2].T_cw.translation().x() = std::nan("");
    EXPECT_NE(error_of([&] { (void)optimize_pose_graph(nodes, r.edges); }).find("non-finite"),
              std::string::npos);
  }
  PoseGraphParams params;
  params.iterations = -1;
  EXPECT_NE(error_of([&] { (void)optimize_pose_graph(r.nodes, r.edges, params); }).find("iterations"),
            std::string::npos);
  params = {};
  params.translation_weight = -1.0;
  EXPECT_NE(error_of([&] { (void)optimize_pose_graph(r.nodes, r.edges, params); }).find("weight"),
            std::string::npos);
}
