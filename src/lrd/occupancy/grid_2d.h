#pragma once
// The 2-D occupancy grid a planner reads (docs/occupancy.md): the voxels between two heights above
// the floor, projected onto it. Written in ROS map_server's format (PGM + YAML) and as a picture
// with the trajectory; the ROS node publishes it as nav_msgs/OccupancyGrid.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "lrd/occupancy/floor_frame.h"
#include "lrd/occupancy/occupancy_map.h"

namespace lrd::occupancy {

constexpr std::int8_t kUnknown = -1;
constexpr std::int8_t kFree = 0;
constexpr std::int8_t kOccupied = 100;

struct Grid2d {
  double resolution = 0.05;
  int width = 0, height = 0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // floor coordinates of cell (0, 0)'s outer corner
  std::vector<std::int8_t> cells;                    // row-major from (0, 0), y up (OccupancyGrid order)
  FloorFrame floor;                                  // where the grid lies in the map frame
  double min_height = 0.0, max_height = 0.0;         // the band of voxels it shows, above the floor

  [[nodiscard]] std::int8_t at(int x, int y) const { return cells[static_cast<std::size_t>(y) * width + x]; }
  // The cell holding floor coordinates (x, y); false outside the grid.
  [[nodiscard]] bool cell_of(const Eigen::Vector2d& xy, int& x, int& y) const;
  [[nodiscard]] std::size_t count(std::int8_t value) const;
};

// Cells with an occupied voxel between min_height and max_height above the floor are occupied;
// else free with a free voxel there; else unknown. One voxel = one cell (same resolution).
// filter_speckles: an occupied voxel with no occupied neighbour (of 26) is left out, as
// octomap_server's speckle filter does (a lone voxel is what a mask's miss of a foot leaves).
[[nodiscard]] Grid2d project_to_grid(const OccupancyMap& map, const FloorFrame& floor, double min_height,
                                     double max_height, bool filter_speckles = true);

struct MapServerThresholds {
  double occupied = 0.65;
  double free = 0.196;
};

// OUT/STEM.pgm and OUT/STEM.yaml as ROS map_server reads them (negate 0: occupied black 0, free
// white 254, unknown 205). The YAML also carries the floor frame (`lrd_floor_frame`), which
// map_server ignores, so the grid can be put back into the SLAM map frame.
void write_map_server(const Grid2d& grid, const std::filesystem::path& out, const std::string& stem,
                      const MapServerThresholds& thresholds = {});
// Reads a map_server YAML and its image (the thresholds decide each cell as map_server does).
// Throws lrd::Error naming the file and the problem.
[[nodiscard]] Grid2d read_map_server(const std::filesystem::path& yaml);

// The grid for people: free white, occupied black, unknown grey, the trajectory (map-frame camera
// positions) drawn in blue from a green start to a red end, scaled up to about 800 pixels.
void write_grid_picture(const Grid2d& grid, const std::vector<Eigen::Vector3d>& trajectory,
                        const std::filesystem::path& file);

}  // namespace lrd::occupancy
