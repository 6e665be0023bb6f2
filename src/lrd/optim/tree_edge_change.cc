#include "lrd/optim/tree_edge_change.h"

#include <algorithm>
#include <cmath>

#include "lrd/map/keyframe.h"

namespace lrd::optim {

TreeEdgeChange largest_tree_edge_change(const std::vector<map::KeyFrame*>& keyframes, const PoseOf& before,
                                        const PoseOf& after,
                                        const std::function<bool(const map::KeyFrame*)>& counted) {
  TreeEdgeChange worst;
  for (map::KeyFrame* k : keyframes) {
    map::KeyFrame* parent = k->parent();
    if (k->is_bad() || parent == nullptr || parent->is_bad()) continue;
    if (counted && (!counted(k) || !counted(parent))) continue;
    const Eigen::Isometry3d rel_before = before(k) * before(parent).inverse();
    const Eigen::Isometry3d rel_after = after(k) * after(parent).inverse();
    const Eigen::Isometry3d change = rel_before.inverse() * rel_after;
    const double metres = change.translation().norm();
    const double degrees = Eigen::AngleAxisd(change.linear()).angle() * 180.0 / M_PI;
    if (metres > worst.metres) worst.keyframe = k->id();
    worst.metres = std::max(worst.metres, metres);
    worst.degrees = std::max(worst.degrees, degrees);
  }
  return worst;
}

}  // namespace lrd::optim
