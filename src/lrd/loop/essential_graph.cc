#include "lrd/loop/essential_graph.h"

#include <algorithm>
#include <unordered_map>

#include "lrd/map/keyframe.h"

namespace lrd::loop {

void EssentialGraph::add_edge(const map::KeyFrame* from, const map::KeyFrame* to,
                              const Eigen::Isometry3d& T_to_from) {
  const std::pair<std::uint64_t, std::uint64_t> key = std::minmax(from->id(), to->id());
  if (!inserted_.insert(key).second) return;
  edges.push_back({from->id(), to->id(), T_to_from, 1.0});
}

void EssentialGraph::add_map_edges(const std::vector<map::KeyFrame*>& keyframes, const PoseOf& pose,
                                   int min_weight) {
  std::unordered_map<std::uint64_t, map::KeyFrame*> by_id;
  for (map::KeyFrame* k : keyframes) by_id.emplace(k->id(), k);
  for (map::KeyFrame* k : keyframes) {
    const Eigen::Isometry3d T_kw = pose(k);
    auto relative = [&](map::KeyFrame* n) { return pose(n) * T_kw.inverse(); };
    if (map::KeyFrame* parent = k->parent(); parent != nullptr && !parent->is_bad())
      add_edge(k, parent, relative(parent));
    for (map::KeyFrame* l : k->loop_edges())
      if (!l->is_bad() && l->id() < k->id()) add_edge(k, l, relative(l));
    for (map::KeyFrame* n : k->covisibles_with_weight(min_weight)) {
      if (n->is_bad() || n->id() >= k->id() || n == k->parent() || n->parent() == k ||
          k->loop_edges().count(n) != 0)
        continue;
      add_edge(k, n, relative(n));
    }
    // The camera trajectory passes between tracking-linked keyframes from one frame to the next:
    // a correction must bend the map elsewhere (optim/odometry_change.h checks that it did).
    for (const auto& [id, tracked] : k->tracking_links()) {
      const auto it = by_id.find(id);
      if (id < k->id() && it != by_id.end() && !it->second->is_bad())
        add_edge(k, it->second, relative(it->second));
    }
  }
}

optim::PoseGraphResult EssentialGraph::solve(const std::vector<map::KeyFrame*>& keyframes,
                                             const PoseOf& start, const map::KeyFrame* fixed,
                                             int iterations) const {
  std::vector<optim::PoseGraphNode> nodes;
  nodes.reserve(keyframes.size());
  for (map::KeyFrame* k : keyframes) nodes.push_back({k->id(), start(k), k == fixed});
  optim::PoseGraphParams params;
  params.iterations = iterations;
  return optim::optimize_pose_graph(nodes, edges, params);
}

}  // namespace lrd::loop
