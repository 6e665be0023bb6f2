#pragma once
// Essential graphs of any size shaped like loop closing's (bench_scale, bench/results/scale.md): a
// camera touring a room in laps, `keyframes_per_lap` keyframes a lap; each keyframe linked to its
// spanning-tree parent (the previous one), to its strongest covisible neighbours (the ones just
// before it, up to `edges_per_keyframe` edges in all) and to the keyframe a lap before (the map's
// revisits); odometry drift accumulated along the chain, and the new loop edge from the last
// keyframe to the first lap measured without drift. It times optimize_pose_graph at a map size no
// run of ours reaches by loop detection (the map stops growing in one room).
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "lrd/optim/pose_graph_optimizer.h"

namespace lrd::bench {

struct PoseGraphTiming {
  int keyframes = 0;
  std::size_t edges = 0;
  double seconds = 0.0;
  double initial_cost = 0.0, final_cost = 0.0;
  double drift_before_m = 0.0, error_after_m = 0.0;  // last keyframe against its true position
};

inline Eigen::Isometry3d tour_pose(int k, int keyframes_per_lap) {
  const double theta = 2.0 * M_PI * k / keyframes_per_lap;
  Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
  T_wc.linear() = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_wc.translation() = Eigen::Vector3d(0.65 * std::cos(theta), 0.65 * std::sin(theta), 0.0);
  return T_wc;
}

inline PoseGraphTiming time_synthetic_pose_graph(int keyframes, double edges_per_keyframe,
                                                 int keyframes_per_lap = 30, int iterations = 20) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<Eigen::Isometry3d> truth_cw, drifted_cw;
  Eigen::Isometry3d drift = Eigen::Isometry3d::Identity();
  for (int k = 0; k < keyframes; ++k) {
    const Eigen::Isometry3d T_wc = tour_pose(k, keyframes_per_lap);
    // Odometry error of ~2 mm and 0.05 deg per keyframe, compounding along the chain.
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.linear() = Eigen::AngleAxisd(0.0009 * noise(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    step.translation() = 0.002 * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    drift = drift * step;
    const Eigen::Isometry3d drifted_wc = drift * T_wc;
    truth_cw.push_back(T_wc.inverse());
    drifted_cw.push_back(drifted_wc.inverse());
  }
  std::vector<optim::PoseGraphNode> nodes;
  for (int k = 0; k < keyframes; ++k) {
    optim::PoseGraphNode node;
    node.id = static_cast<std::uint64_t>(k);
    node.T_cw = drifted_cw[static_cast<std::size_t>(k)];
    node.fixed = k == 0;
    nodes.push_back(node);
  }
  std::vector<optim::PoseGraphEdge> edges;
  auto link = [&](int from, int to, const std::vector<Eigen::Isometry3d>& poses) {
    optim::PoseGraphEdge edge;
    edge.from = static_cast<std::uint64_t>(from);
    edge.to = static_cast<std::uint64_t>(to);
    const Eigen::Isometry3d T_fw_inverse = poses[static_cast<std::size_t>(from)].inverse();
    edge.T_to_from = poses[static_cast<std::size_t>(to)] * T_fw_inverse;
    edges.push_back(edge);
  };
  // Parent, one lap back, then covisible neighbours until the edge budget is spent (all measured
  // with the drifted poses, as loop closing measures them before the correction).
  const int covisible = std::max(0, static_cast<int>(std::lround(edges_per_keyframe)) - 2);
  for (int k = 1; k < keyframes; ++k) {
    link(k, k - 1, drifted_cw);
    if (k >= keyframes_per_lap) link(k, k - keyframes_per_lap, drifted_cw);
    for (int j = 2; j <= covisible + 1 && k - j >= 0; ++j) link(k, k - j, drifted_cw);
  }
  // The loop: the last keyframe seen again from the first lap, measured without drift.
  const int last = keyframes - 1, loop = last % keyframes_per_lap;
  link(last, loop, truth_cw);
  optim::PoseGraphParams params;
  params.iterations = iterations;
  const auto t0 = std::chrono::steady_clock::now();
  const optim::PoseGraphResult r = optim::optimize_pose_graph(nodes, edges, params);
  PoseGraphTiming out;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.keyframes = keyframes;
  out.edges = edges.size();
  out.initial_cost = r.initial_cost;
  out.final_cost = r.final_cost;
  const auto centre = [](const Eigen::Isometry3d& T_cw) -> Eigen::Vector3d {
    const Eigen::Isometry3d T_wc = T_cw.inverse();
    return T_wc.translation();
  };
  const auto l = static_cast<std::size_t>(last);
  out.drift_before_m = (centre(drifted_cw[l]) - centre(truth_cw[l])).norm();
  out.error_after_m = (centre(r.T_cw.at(static_cast<std::uint64_t>(last))) - centre(truth_cw[l])).norm();
  return out;
}

}  // namespace lrd::bench
