#pragma once
// Nearest-neighbour queries within a fixed radius: points hashed into cubes of the radius, a query
// looks at the 27 cubes around it. The map evaluators (dense map, occupancy) use it.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "lrd/dense/voxel_key.h"
#include "lrd/util/error.h"

namespace lrd::eval {

// Points hashed into cubes of the search radius: a query looks at the 27 cubes around it.
class PointGrid {
 public:
  PointGrid(const std::vector<Eigen::Vector3f>& points, double cell) : points_(points), inv_(1.0 / cell) {
    if (!(cell > 0.0)) throw Error("map accuracy: the distance threshold must be > 0");
    cells_.reserve(points.size() / 4 + 1);
    for (std::size_t i = 0; i < points.size(); ++i)
      if (points[i].allFinite()) cells_[key(cell_of(points[i]))].push_back(static_cast<std::uint32_t>(i));
  }

  // Distance to the nearest point if one lies within the cell size, else infinity.
  [[nodiscard]] double nearest(const Eigen::Vector3f& p) const {
    std::size_t index = 0;
    return nearest(p, index);
  }
  // The same, with the nearest point's index (set only when the distance is finite).
  [[nodiscard]] double nearest(const Eigen::Vector3f& p, std::size_t& index) const {
    if (!p.allFinite()) return std::numeric_limits<double>::infinity();
    const Eigen::Vector3i c = cell_of(p);
    float best = std::numeric_limits<float>::infinity();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (std::uint32_t i : it->second)
            if (const float d2 = (points_[i] - p).squaredNorm(); d2 < best) {
              best = d2;
              index = i;
            }
        }
    const double d = std::sqrt(static_cast<double>(best));
    return d <= 1.0 / inv_ ? d : std::numeric_limits<double>::infinity();
  }

 private:
  [[nodiscard]] Eigen::Vector3i cell_of(const Eigen::Vector3f& p) const {
    return {static_cast<int>(std::floor(p.x() * inv_)), static_cast<int>(std::floor(p.y() * inv_)),
            static_cast<int>(std::floor(p.z() * inv_))};
  }
  static std::uint64_t key(const Eigen::Vector3i& c) { return dense::voxel_key(c.x(), c.y(), c.z()); }
  const std::vector<Eigen::Vector3f>& points_;
  double inv_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace lrd::eval
