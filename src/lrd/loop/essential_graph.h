#pragma once
// The essential graph a loop correction optimizes (ORB-SLAM2's OptimizeEssentialGraph): the
// spanning tree, earlier loop edges, strong covisibility edges and the tracking links (keyframes
// consecutive frames were tracked against; KeyFrame::tracking_links), each measured with the poses
// the caller gives (before the correction: the drift they hold is what the optimization spreads
// along the loop), one edge per keyframe pair.
#include <Eigen/Geometry>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "lrd/optim/odometry_change.h"
#include "lrd/optim/pose_graph_optimizer.h"

namespace lrd::map {
class KeyFrame;
}

namespace lrd::loop {

using optim::PoseOf;

struct EssentialGraph {
  std::vector<optim::PoseGraphEdge> edges;

  // Adds the edge from -> to (measured T_to_from) unless the pair has one already: a new link
  // across the loop is measured with the corrected poses only (ORB-SLAM2's sInsertedEdges).
  void add_edge(const map::KeyFrame* from, const map::KeyFrame* to, const Eigen::Isometry3d& T_to_from);
  // The spanning tree, loop edges, covisibility edges of weight >= min_weight and tracking links
  // among `keyframes` (bad ones skipped), measured with `pose`.
  void add_map_edges(const std::vector<map::KeyFrame*>& keyframes, const PoseOf& pose, int min_weight);
  // Optimizes the poses of `keyframes` over these edges from the poses `start` gives, `fixed`
  // held still (the gauge).
  [[nodiscard]] optim::PoseGraphResult solve(const std::vector<map::KeyFrame*>& keyframes,
                                             const PoseOf& start, const map::KeyFrame* fixed,
                                             int iterations) const;

 private:
  std::set<std::pair<std::uint64_t, std::uint64_t>> inserted_;
};

}  // namespace lrd::loop
