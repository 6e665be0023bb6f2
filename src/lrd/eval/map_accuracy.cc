#include "lrd/eval/map_accuracy.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "lrd/eval/point_grid.h"
#include "lrd/util/error.h"

namespace lrd::eval {

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
