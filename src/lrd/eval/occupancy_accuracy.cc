#include "lrd/eval/occupancy_accuracy.h"

#include <fmt/format.h>

#include <cmath>
#include <set>
#include <unordered_map>

#include "lrd/dense/voxel_key.h"
#include "lrd/eval/point_grid.h"

namespace lrd::eval {

namespace {
std::vector<Eigen::Vector3f> on_floor(const std::vector<Eigen::Vector3f>& points) {
  std::vector<Eigen::Vector3f> out;
  out.reserve(points.size());
  for (const Eigen::Vector3f& p : points) out.emplace_back(p.x(), p.y(), 0.0f);
  return out;
}
bool in_band(const Eigen::Vector3f& p, const OccupancyTruth& t) {
  return p.z() >= t.min_height && p.z() <= t.max_height;
}

// Seen samples grouped by their voxel (cell_size): a group counts once, recalled when any of its
// samples has a map element within the grid's radius.
std::pair<std::size_t, std::size_t> recall_by_voxel(const std::vector<Eigen::Vector3f>& samples,
                                                    const std::vector<char>& use, const PointGrid& map,
                                                    double cell_size) {
  std::unordered_map<std::uint64_t, bool> voxels;
  const double inv = 1.0 / cell_size;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!use[i]) continue;
    bool& recalled = voxels[dense::voxel_key(samples[i], inv)];
    if (!recalled) recalled = std::isfinite(map.nearest(samples[i]));
  }
  std::size_t recalled = 0;
  for (const auto& [key, r] : voxels) recalled += r;
  return {voxels.size(), recalled};
}
}  // namespace

OccupancyAccuracy evaluate_occupancy(const std::vector<Eigen::Vector3f>& occupied,
                                     const std::vector<Eigen::Vector3f>& cells,
                                     const std::vector<std::int8_t>& cell_states, const OccupancyTruth& truth,
                                     double resolution) {
  OccupancyAccuracy a;
  a.resolution = resolution;
  const double inv = 1.0 / resolution;
  // 3-D.
  const PointGrid scene(truth.scene, resolution);
  const PointGrid people(truth.people, resolution);
  std::set<std::uint64_t> people_voxels;
  for (const Eigen::Vector3f& p : truth.people)
    if (!std::isfinite(scene.nearest(p))) people_voxels.insert(dense::voxel_key(p, inv));
  a.people_voxels = people_voxels.size();
  a.occupied_voxels = occupied.size();
  for (const Eigen::Vector3f& v : occupied) {
    if (std::isfinite(scene.nearest(v)))
      ++a.matching_voxels;
    else if (std::isfinite(people.nearest(v)))
      ++a.people_ghosts;
  }
  const PointGrid map(occupied, resolution);
  std::tie(a.seen_scene_voxels, a.recalled_scene_voxels) =
      recall_by_voxel(truth.scene, truth.seen, map, resolution);

  // 2-D: on the floor plane, the band's samples only.
  std::vector<Eigen::Vector3f> band_scene;
  std::vector<char> band_seen;
  for (std::size_t i = 0; i < truth.scene.size(); ++i)
    if (in_band(truth.scene[i], truth)) {
      band_scene.emplace_back(truth.scene[i].x(), truth.scene[i].y(), 0.0f);
      band_seen.push_back(i < truth.seen.size() ? truth.seen[i] : 0);
    }
  const PointGrid scene_2d(band_scene, resolution);
  std::vector<Eigen::Vector3f> occupied_cells;
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (cell_states[i] == 100) occupied_cells.emplace_back(cells[i].x(), cells[i].y(), 0.0f);
  a.grid_occupied_cells = occupied_cells.size();
  for (const Eigen::Vector3f& c : occupied_cells) a.grid_matching_cells += std::isfinite(scene_2d.nearest(c));
  const PointGrid occupied_2d(occupied_cells, resolution);
  std::tie(a.seen_scene_cells, a.recalled_scene_cells) =
      recall_by_voxel(band_scene, band_seen, occupied_2d, resolution);

  // The people's path: the grid cell under each of their points in the band (nearest cell centre
  // within half a diagonal), unless a static obstacle is within two cells of the cell's centre
  // (then the cell may hold the obstacle itself: judged from the person's points instead, a cell
  // 8 cm from walking_rpy's wall counted as a walker's path, and the wall's voxels blocked it).
  const std::vector<Eigen::Vector3f> cells_2d = on_floor(cells);
  const PointGrid all_cells(cells_2d, resolution);
  const PointGrid near_obstacles(band_scene, 2.0 * resolution);
  std::set<std::size_t> path;
  for (const Eigen::Vector3f& p : truth.people) {
    if (!in_band(p, truth)) continue;
    std::size_t cell = 0;
    if (all_cells.nearest(Eigen::Vector3f(p.x(), p.y(), 0.0f), cell) > resolution * 0.7072) continue;
    if (!std::isfinite(near_obstacles.nearest(cells_2d[cell]))) path.insert(cell);
  }
  a.path_cells = path.size();
  for (std::size_t c : path) {
    a.path_free_cells += cell_states[c] == 0;
    if (cell_states[c] != 100) continue;
    ++a.path_blocked_cells;
    a.blocked_path_cells.emplace_back(cells[c].x(), cells[c].y());
  }
  return a;
}

std::string describe(const OccupancyAccuracy& a) {
  std::string where;
  constexpr std::size_t kShown = 5;
  for (std::size_t i = 0; i < a.blocked_path_cells.size() && i < kShown; ++i)
    where += fmt::format("{}({:.2f}, {:.2f})", i == 0 ? " at " : " ", a.blocked_path_cells[i].x(),
                         a.blocked_path_cells[i].y());
  if (a.blocked_path_cells.size() > kShown) where += " ...";
  return fmt::format(
      "occupied voxels: precision {:.1f} %, recall {:.1f} % at {:.0f} cm; {} people ghosts ({:.2f} %); "
      "2-D grid: precision {:.1f} %, recall {:.1f} %; people's path: {} of {} cells blocked{}, {} free",
      100.0 * a.precision(), 100.0 * a.recall(), 100.0 * a.resolution, a.people_ghosts,
      100.0 * a.people_ghost_share(), 100.0 * a.grid_precision(), 100.0 * a.grid_recall(),
      a.path_blocked_cells, a.path_cells, where, a.path_free_cells);
}

}  // namespace lrd::eval
