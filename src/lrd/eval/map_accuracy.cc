#include "lrd/eval/map_accuracy.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "lrd/dense/voxel_key.h"
#include "lrd/util/error.h"

namespace lrd::eval {

namespace {

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
    if (!p.allFinite()) return std::numeric_limits<double>::infinity();
    const Eigen::Vector3i c = cell_of(p);
    float best = std::numeric_limits<float>::infinity();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (std::uint32_t i : it->second) best = std::min(best, (points_[i] - p).squaredNorm());
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

}  // namespace

std::vector<char> seen_samples(const std::vector<Eigen::Vector3f>& samples,
                               const camera::PinholeCamera& camera, const std::vector<TruthView>& views,
                               double max_depth) {
  std::vector<char> seen(samples.size(), 0);
  for (const TruthView& v : views) {
    const Eigen::Isometry3f T = v.T_cw.cast<float>();
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (seen[i]) continue;
      const Eigen::Vector3f p = T * samples[i];
      if (p.z() < 0.1f || p.z() > max_depth) continue;
      const int u = static_cast<int>(std::lround(camera.fx * p.x() / p.z() + camera.cx));
      const int r = static_cast<int>(std::lround(camera.fy * p.y() / p.z() + camera.cy));
      if (u < 0 || r < 0 || u >= v.depth.cols || r >= v.depth.rows) continue;
      if (!v.dynamic.empty() && v.dynamic.at<unsigned char>(r, u) != 0) continue;
      const float z = v.depth.at<float>(r, u);
      if (z > 0.0f && std::abs(z - p.z()) < 0.03f + 0.01f * p.z()) seen[i] = 1;
    }
  }
  return seen;
}

std::string describe(const MapAccuracy& a) {
  return fmt::format(
      "{:.2f} % of {} points farther than {:.0f} cm (ghosts), completeness {:.1f} % of {} seen scene "
      "samples, median distance {:.1f} mm",
      100.0 * a.ghost_ratio(), a.map_points, 100.0 * a.threshold, 100.0 * a.completeness(), a.seen_samples,
      1e3 * a.median_distance);
}

MapAccuracy evaluate_map(const std::vector<Eigen::Vector3f>& map, const std::vector<Eigen::Vector3f>& scene,
                         const std::vector<char>& seen, double threshold) {
  MapAccuracy a;
  a.threshold = threshold;
  a.map_points = map.size();
  const PointGrid scene_grid(scene, threshold);
  std::vector<double> d(map.size());
  for (std::size_t i = 0; i < map.size(); ++i) {
    d[i] = scene_grid.nearest(map[i]);
    if (!std::isfinite(d[i])) ++a.ghost_points;
  }
  if (!d.empty()) {
    std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
    a.median_distance = std::min(d[d.size() / 2], threshold);  // capped: more than half are ghosts
  }
  const PointGrid map_grid(map, threshold);
  for (std::size_t i = 0; i < scene.size() && i < seen.size(); ++i) {
    if (!seen[i]) continue;
    ++a.seen_samples;
    if (std::isfinite(map_grid.nearest(scene[i]))) ++a.covered_samples;
  }
  return a;
}

}  // namespace lrd::eval
