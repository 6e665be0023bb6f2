#pragma once
// How much a solution (a pose graph's, a global BA's) changes the spanning tree's edges: each
// keyframe's pose relative to its parent, after against before. Odometry between two keyframes a
// fraction of a second apart is never wrong by decimetres, so a solution that changes one edge
// that much has not spread a drift but torn the map (reliability issue, item 1).
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <vector>

namespace lrd::map {
class KeyFrame;
}

namespace lrd::optim {

// World-to-camera pose of a keyframe under one solution (or before it).
using PoseOf = std::function<Eigen::Isometry3d(map::KeyFrame*)>;

struct TreeEdgeChange {
  double metres = 0.0;
  double degrees = 0.0;
  std::uint64_t keyframe = 0;  // the child of the edge whose position changed most
};

// Over the edges between `keyframes` and their parents (bad ones skipped; with `counted`, only
// edges whose child and parent it accepts).
[[nodiscard]] TreeEdgeChange largest_tree_edge_change(
    const std::vector<map::KeyFrame*>& keyframes, const PoseOf& before, const PoseOf& after,
    const std::function<bool(const map::KeyFrame*)>& counted = {});

}  // namespace lrd::optim
