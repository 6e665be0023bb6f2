#include "lrd/optim/pose_graph_optimizer.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <unordered_map>

#include "lrd/geometry/se3.h"
#include "lrd/util/error.h"

namespace lrd::optim {
namespace {

// A pose as one Ceres block: the rotation of T_cw as an Eigen-ordered quaternion (x, y, z, w), then
// its translation, on the product of EigenQuaternionManifold and R^3 (6 degrees of freedom). With
// a multiplicative update no rotation is singular: keyframes all round a room reach angles of pi,
// where angle-axis blocks degrade.
using QuaternionPoseBlock = std::array<double, 7>;
using PoseManifold = ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>;

QuaternionPoseBlock to_quaternion_block(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q = Eigen::Quaterniond(T.linear()).normalized();
  const Eigen::Vector3d t = T.translation();
  return {q.x(), q.y(), q.z(), q.w(), t.x(), t.y(), t.z()};
}

Eigen::Isometry3d from_quaternion_block(const QuaternionPoseBlock& b) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(b[3], b[0], b[1], b[2]).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(b[4], b[5], b[6]);
  return geometry::orthonormalized(T);
}

// r = (angle_axis(R_E), t_E) of E = T_to_from^-1 * T_to * T_from^-1, scaled by the square roots
// of the information weights.
struct EdgeError {
  Eigen::Quaterniond q_meas_inv;  // rotation of T_to_from^-1
  Eigen::Vector3d t_meas_inv;     // translation of T_to_from^-1
  double sqrt_w_rot, sqrt_w_trans;

  template <class T>
  bool operator()(const T* from, const T* to, T* r) const {
    using Vec3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Eigen::Quaternion<T>> q_from(from), q_to(to);
    const Eigen::Map<const Vec3> t_from(from + 4), t_to(to + 4);
    // T_to * T_from^-1; the manifold keeps the quaternions unit, so conjugate() is the inverse.
    const Eigen::Quaternion<T> q_rel = q_to * q_from.conjugate();
    const Vec3 t_rel = t_to - q_rel * t_from;
    const Eigen::Quaternion<T> q_m = q_meas_inv.cast<T>();
    const Eigen::Quaternion<T> q_e = q_m * q_rel;
    const Vec3 t_e = q_m * t_rel + t_meas_inv.cast<T>();
    // Ceres wants (w, x, y, z); it also picks the short way round for w < 0.
    const T wxyz[4] = {q_e.w(), q_e.x(), q_e.y(), q_e.z()};
    ceres::QuaternionToAngleAxis(wxyz, r);
    for (int i = 0; i < 3; ++i) {
      r[i] *= sqrt_w_rot;
      r[3 + i] = t_e[i] * sqrt_w_trans;
    }
    return true;
  }
};

bool finite(const Eigen::Isometry3d& T) {
  return T.matrix().allFinite();
}

bool positive(double w) {
  return std::isfinite(w) && w > 0.0;
}

std::string edge_name(std::size_t i, const PoseGraphEdge& e) {
  return "edge " + std::to_string(i) + " (" + std::to_string(e.from) + " -> " + std::to_string(e.to) + ")";
}

void validate(const std::vector<PoseGraphNode>& nodes, const std::vector<PoseGraphEdge>& edges,
              const PoseGraphParams& params, const std::unordered_map<std::uint64_t, std::size_t>& index) {
  auto fail = [](const std::string& what) { throw Error("pose graph: " + what); };
  if (params.iterations < 0) fail("iterations must be >= 0, got " + std::to_string(params.iterations));
  if (!positive(params.rotation_weight) || !positive(params.translation_weight))
    fail("rotation_weight and translation_weight must be finite and > 0");
  bool any_fixed = false;
  for (const PoseGraphNode& n : nodes) {
    if (!finite(n.T_cw)) fail("node " + std::to_string(n.id) + " has a non-finite pose");
    any_fixed = any_fixed || n.fixed;
  }
  // A free gauge would leave the solution drifting along it: the caller must anchor the world.
  if (!any_fixed) fail("no fixed node (fix at least one, e.g. the first keyframe)");
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const PoseGraphEdge& e = edges[i];
    if (!index.contains(e.from)) fail(edge_name(i, e) + " refers to unknown node " + std::to_string(e.from));
    if (!index.contains(e.to)) fail(edge_name(i, e) + " refers to unknown node " + std::to_string(e.to));
    if (e.from == e.to) fail(edge_name(i, e) + " connects a node to itself");
    if (!finite(e.T_to_from)) fail(edge_name(i, e) + " has a non-finite measurement");
    if (!positive(e.weight)) fail(edge_name(i, e) + " weight must be finite and > 0");
  }
}

}  // namespace

PoseGraphResult optimize_pose_graph(const std::vector<PoseGraphNode>& nodes,
                                    const std::vector<PoseGraphEdge>& edges, const PoseGraphParams& params) {
  std::unordered_map<std::uint64_t, std::size_t> index;
  index.reserve(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (!index.emplace(nodes[i].id, i).second)
      throw Error("pose graph: duplicate node id " + std::to_string(nodes[i].id));
  validate(nodes, edges, params, index);

  PoseGraphResult result;
  for (const PoseGraphNode& n : nodes) result.T_cw[n.id] = geometry::orthonormalized(n.T_cw);
  if (edges.empty()) return result;

  // Sized once: Ceres keeps pointers into it.
  std::vector<QuaternionPoseBlock> blocks(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) blocks[i] = to_quaternion_block(nodes[i].T_cw);

  // Declared before the problem, which does not own it and must not outlive it.
  PoseManifold pose_manifold;
  ceres::Problem::Options popts;
  popts.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(popts);
  for (const PoseGraphEdge& e : edges) {
    const Eigen::Isometry3d meas_inv = e.T_to_from.inverse();
    auto* functor = new EdgeError{Eigen::Quaterniond(meas_inv.linear()).normalized(), meas_inv.translation(),
                                  std::sqrt(e.weight * params.rotation_weight),
                                  std::sqrt(e.weight * params.translation_weight)};
    auto* cost = new ceres::AutoDiffCostFunction<EdgeError, 6, 7, 7>(functor);
    problem.AddResidualBlock(cost, nullptr, blocks[index.at(e.from)].data(), blocks[index.at(e.to)].data());
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    double* b = blocks[i].data();
    if (!problem.HasParameterBlock(b)) continue;  // in no edge
    problem.SetManifold(b, &pose_manifold);
    if (nodes[i].fixed) problem.SetParameterBlockConstant(b);
  }

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  // Eigen's simplicial Cholesky: no BLAS threads under it, so bit-for-bit repeatable; CHOLMOD
  // was no faster on a 300-node / 3000-edge graph.
  options.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
  options.num_threads = 1;
  options.max_num_iterations = params.iterations;
  // Tighter than Ceres' defaults, nearer ORB-SLAM2's g2o, which runs all its iterations: the
  // default 1e-6 relative cost change stopped a 300-node loop correction 2 iterations early.
  options.function_tolerance = 1e-12;
  options.parameter_tolerance = 1e-12;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (summary.termination_type == ceres::FAILURE)
    throw Error("pose graph: the solver failed: " + summary.message);

  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  // Entry 0 is the start; there are none when every block is constant.
  result.iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (!nodes[i].fixed && problem.HasParameterBlock(blocks[i].data()))
      result.T_cw[nodes[i].id] = from_quaternion_block(blocks[i]);
  return result;
}

}  // namespace lrd::optim
