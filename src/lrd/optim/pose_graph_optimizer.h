#pragma once
// Pose-graph optimization over SE(3) for loop closing (ORB-SLAM2's OptimizeEssentialGraph, with
// the scale fixed: RGB-D measures it, so Sim(3) is not needed), on Ceres.
//
// Each edge measures the relative pose T_to_from of two nodes; its residual is the 6-vector
//   E = T_to_from^-1 * T_cw[to] * T_cw[from]^-1,   r = (angle_axis(R_E), t_E)
// i.e. the rotation part is the exact SO(3) log of E and the translation part is E's translation
// (it agrees with the se(3) log's nu to first order, and is zero exactly when E is). The cost is
//   sum_edges 0.5 * weight * (rotation_weight * |r_rot|^2 + translation_weight * |r_trans|^2),
// so `weight`, `rotation_weight` and `translation_weight` are information (inverse variance)
// scales, like a g2o information matrix weight * I (ORB-SLAM2 uses I for every edge).
//
// The gauge: at least one node must be `fixed` (lrd::Error otherwise; ORB-SLAM2 fixes the first
// keyframe, which defines the world frame). A connected part of the graph that reaches no fixed
// node is held only by Levenberg-Marquardt damping: it converges, but where it ends up along its
// gauge freedom is arbitrary. Fixed nodes and nodes in no edge are returned as given
// (orthonormalized).
//
// Deterministic: one thread, Eigen's sparse Cholesky (no multithreaded BLAS underneath).
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <vector>

namespace lrd::optim {

struct PoseGraphNode {
  std::uint64_t id = 0;
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();  // world-to-camera; the initial estimate
  bool fixed = false;                                      // held at T_cw
};

struct PoseGraphEdge {
  std::uint64_t from = 0;
  std::uint64_t to = 0;
  // Measured relative pose: maps points from camera `from` to camera `to`, i.e. ideally
  // T_cw[to] * T_cw[from].inverse().
  Eigen::Isometry3d T_to_from = Eigen::Isometry3d::Identity();
  double weight = 1.0;  // information scale, > 0
};

struct PoseGraphParams {
  int iterations = 20;              // Levenberg-Marquardt iterations at most, >= 0
  double rotation_weight = 1.0;     // information of the rotation residual (rad^-2), > 0
  double translation_weight = 1.0;  // information of the translation residual (m^-2), > 0
};

struct PoseGraphResult {
  std::map<std::uint64_t, Eigen::Isometry3d> T_cw;  // every node, orthonormalized
  double initial_cost = 0.0;                        // the cost above, before and after
  double final_cost = 0.0;
  int iterations = 0;  // Levenberg-Marquardt steps taken (successful or not)
};

// lrd::Error: duplicate node ids, no fixed node, an edge naming an unknown node or the same node
// twice, a non-finite pose, a weight that is not finite and > 0, or iterations < 0.
[[nodiscard]] PoseGraphResult optimize_pose_graph(const std::vector<PoseGraphNode>& nodes,
                                                  const std::vector<PoseGraphEdge>& edges,
                                                  const PoseGraphParams& params = {});

}  // namespace lrd::optim
