#pragma once
// How good an occupancy map is against the synthetic scene (the bars in docs/occupancy.md),
// everything in the scene's world frame (z up, floor at z = 0). A voxel or cell "matches" a surface
// when a sample of it lies within one resolution of its centre (in 3-D for voxels, on the floor
// plane for cells).
//  - precision: occupied voxels matching a static surface; recall: seen scene voxels (the scene
//    samples some frame saw, voxelized) with an occupied voxel matching one of their samples;
//  - people ghosts: occupied voxels matching no static surface but a surface of a person seen
//    during the sequence (the masks' pixels of the sensor's depth);
//  - the 2-D grid: the same against the scene samples between the grid's heights, and the
//    people's path (their points in those heights, more than two cells from static obstacles): how
//    many of its cells the grid blocks.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace lrd::eval {

struct OccupancyAccuracy {
  double resolution = 0.05;
  std::size_t occupied_voxels = 0, matching_voxels = 0;
  std::size_t seen_scene_voxels = 0, recalled_scene_voxels = 0;
  std::size_t people_voxels = 0;  // voxels the people's seen surfaces occupied at some time
  std::size_t people_ghosts = 0;  // occupied map voxels on them and on no static surface
  std::size_t grid_occupied_cells = 0, grid_matching_cells = 0;
  std::size_t seen_scene_cells = 0, recalled_scene_cells = 0;
  std::size_t path_cells = 0;                       // grid cells the people walked through
  std::size_t path_blocked_cells = 0;               // of those, occupied in the grid
  std::size_t path_free_cells = 0;                  // ... free (the rest unknown)
  std::vector<Eigen::Vector2f> blocked_path_cells;  // where those blocked cells are (x, y)

  [[nodiscard]] static double share(std::size_t part, std::size_t whole) {
    return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
  }
  [[nodiscard]] double precision() const { return share(matching_voxels, occupied_voxels); }
  [[nodiscard]] double recall() const { return share(recalled_scene_voxels, seen_scene_voxels); }
  [[nodiscard]] double people_ghost_share() const { return share(people_ghosts, occupied_voxels); }
  [[nodiscard]] double grid_precision() const { return share(grid_matching_cells, grid_occupied_cells); }
  [[nodiscard]] double grid_recall() const { return share(recalled_scene_cells, seen_scene_cells); }
  [[nodiscard]] double path_blocked_share() const { return share(path_blocked_cells, path_cells); }
};

// Views of the caller's data (a scene has a million samples: not copied).
struct OccupancyTruth {
  const std::vector<Eigen::Vector3f>& scene;   // static surface samples
  const std::vector<char>& seen;               // per scene sample: some frame saw it
  const std::vector<Eigen::Vector3f>& people;  // the people's surfaces as the frames saw them
  double min_height = 0.1, max_height = 1.8;   // the grid's band above the floor (z = 0)
};

// occupied: the map's occupied voxel centres; cells / cell_states: the grid's cell centres (at
// the band's middle height) and their values (-1 unknown, 0 free, 100 occupied).
[[nodiscard]] OccupancyAccuracy evaluate_occupancy(const std::vector<Eigen::Vector3f>& occupied,
                                                   const std::vector<Eigen::Vector3f>& cells,
                                                   const std::vector<std::int8_t>& cell_states,
                                                   const OccupancyTruth& truth, double resolution);

// "occupied voxels: precision 97.1 %, recall 93.4 % at 5 cm; 0 people ghosts (0.00 %); grid:
// precision ..., recall ...; people's path: 0 of 812 cells blocked" (with up to five blocked
// cells' places, so a user can find them on occupancy_2d.png)
[[nodiscard]] std::string describe(const OccupancyAccuracy& a);

}  // namespace lrd::eval
