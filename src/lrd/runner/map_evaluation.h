#pragma once
// Judging the maps of a run on the synthetic benchmark: the dense map (the bars in
// bench/results/dense.md) and the occupancy map (those in docs/occupancy.md) against the sequence's
// scene.ply, in its world frame.
#include <Eigen/Geometry>
#include <filesystem>
#include <vector>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/dense/point_cloud.h"
#include "lrd/eval/map_accuracy.h"
#include "lrd/eval/occupancy_accuracy.h"
#include "lrd/io/trajectory.h"
#include "lrd/occupancy/occupancy_builder.h"

namespace lrd::runner {

// What the maps are judged against: the rigid transform that best maps the estimated camera poses
// onto the true ones (rotations and positions, not positions alone as ATE does: a camera that
// hardly moves leaves the rotation of a position-only fit undetermined), the static scene's
// samples, which of them some frame saw, and the people's surfaces as the frames saw them.
struct SceneTruth {
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();  // estimate's map frame -> world
  dense::PointCloud scene;
  std::vector<char> seen;
  std::vector<Eigen::Vector3f> people;
};

// From `sequence` (scene.ply, groundtruth.txt, depth/, mask/): every `frame_stride`-th frame
// decides what was seen (up to max_depth). Throws lrd::Error naming what is missing.
[[nodiscard]] SceneTruth load_scene_truth(const io::Trajectory& estimate,
                                          const std::filesystem::path& sequence,
                                          const camera::PinholeCamera& camera, double max_depth,
                                          int frame_stride = 5);

// The dense map (in the estimate's map frame).
[[nodiscard]] eval::MapAccuracy evaluate_dense_map(const dense::PointCloud& map, const SceneTruth& truth,
                                                   double threshold = 0.05);

// The occupancy map and its 2-D grid (map frame; the grid's band of heights above the floor).
[[nodiscard]] eval::OccupancyAccuracy evaluate_occupancy(const occupancy::OccupancyMap& map,
                                                         const occupancy::Grid2d& grid,
                                                         const SceneTruth& truth);

}  // namespace lrd::runner
