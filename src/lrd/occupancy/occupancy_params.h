#pragma once
// The `occupancy` section of the config: the 3-D occupancy map (OctoMap) built from the dense
// stage's keyframe views and the 2-D grid a planner reads (docs/occupancy.md). config/default.yaml
// documents every key.
#include <Eigen/Core>
#include <optional>

#include "lrd/config/node_reader.h"

namespace lrd::occupancy {

struct OccupancyParams {
  bool enabled = true;       // with the dense map (lrdslam run --dense or --occupancy)
  double resolution = 0.05;  // m; the voxel edge, and the 2-D grid's cell
  double max_range = 3.0;    // m of depth (z, as dense.max_depth): rays are cut there, free up to it
  double prob_hit = 0.7;     // occupancy probability a ray's end adds when the depth is exact
  double prob_miss = 0.4;    // ... and a voxel a ray passes through
  double clamp_min = 0.12;   // probabilities stay within these (OctoMap's defaults): a voxel can
  double clamp_max = 0.97;   // change its mind after a few views
  // Depth noise sigma(z) = depth_noise * z^2 (m; Kinect-like, Khoshelham & Elberink 2012): a far
  // hit may lie in a neighbouring voxel, so it adds less than prob_hit (occupancy_map.h).
  double depth_noise = 0.0015;
  // Keyframes whose rays must end in a voxel before it counts as a surface (until then its hits
  // wait aside): a part of a walker that the mask missed in one keyframe is somewhere else in the
  // next, so it never becomes an obstacle. 1: every hit counts at once (plain OctoMap).
  int min_hit_keyframes = 2;
  // ... counted only when this far apart in time (s): a walker has moved on ~0.8 m meanwhile.
  double min_hit_interval = 1.0;
  // The 2-D grid: voxels between these heights above the floor (m) are obstacles.
  double min_height = 0.1;
  double max_height = 1.8;
  bool filter_speckles = true;  // lone occupied voxels stay out of the 2-D grid (grid_2d.h)
  // The floor: the map frame's "up" (the first camera's -y: cameras start roughly level) refined
  // to the normal of the dominant horizontal plane; its height along up from the map origin, or
  // none to take the lowest well-supported horizontal plane.
  Eigen::Vector3d up{0.0, -1.0, 0.0};
  std::optional<double> floor_height;
  // map_server's thresholds, written into occupancy_2d.yaml.
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;

  // Reads the `occupancy` section (and finishes it).
  static OccupancyParams from_config(config::NodeReader reader);
};

}  // namespace lrd::occupancy
