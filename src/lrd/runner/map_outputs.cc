#include "lrd/runner/map_outputs.h"

#include <spdlog/spdlog.h>

#include <chrono>

#include "lrd/dense/cloud_renderer.h"
#include "lrd/dense/ply_io.h"
#include "lrd/io/image_file.h"
#include "lrd/runner/map_evaluation.h"
#include "lrd/util/error.h"

namespace lrd::runner {

namespace fs = std::filesystem;

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Writes the dense map and its picture, and judges the repair where the sequence has truth.
DenseReport finish_dense(const System& slam, const RepairRecorder& repairs, const RunOptions& o,
                         const camera::PinholeCamera& camera, const dense::PointCloud& cloud) {
  DenseReport d;
  d.points = cloud.size();
  dense::write_ply(o.out / "dense_map.ply", cloud);
  const io::Trajectory keyframes = slam.keyframe_trajectory();
  if (!keyframes.empty() && cloud.size() > 0) {
    const cv::Mat picture =
        dense::render_cloud(cloud, camera, dense::overview_pose(cloud, keyframes.front().pose));
    io::write_image_file(o.out / "dense_map.png", picture);
  }
  d.repair = slam.repair_totals();
  d.storage = slam.dense_storage();
  if (repairs.has_truth()) {
    const RepairRecorder::DepthError e = repairs.depth_error();
    if (e.pixels > 0) {
      d.repair_median_depth_error = e.median;
      d.repair_compared_pixels = e.pixels;
    }
  }
  return d;
}

OccupancyReport occupancy_report(const occupancy::Occupancy& occ) {
  OccupancyReport r;
  r.resolution = occ.map.resolution();
  r.occupied_voxels = occ.map.occupied_count();
  r.free_voxels = occ.map.free_count();
  r.up = occ.floor.up();
  r.floor_height = occ.floor.height;
  r.grid_width = occ.grid.width;
  r.grid_height = occ.grid.height;
  r.grid_occupied = occ.grid.count(occupancy::kOccupied);
  r.grid_free = occ.grid.count(occupancy::kFree);
  r.grid_unknown = occ.grid.count(occupancy::kUnknown);
  return r;
}
}  // namespace

void finish_maps(RunReport& report, const System& slam, const RepairRecorder& repairs, const RunOptions& o,
                 const io::Trajectory& trajectory, const camera::PinholeCamera& camera,
                 const SystemParams& params) {
  auto t0 = std::chrono::steady_clock::now();
  const dense::PointCloud cloud = slam.dense_map();
  const double assemble_seconds = seconds_since(t0);
  report.dense = finish_dense(slam, repairs, o, camera, cloud);
  report.dense->assemble_seconds = assemble_seconds;

  std::optional<occupancy::Occupancy> occ;
  if (slam.occupancy_enabled()) {
    t0 = std::chrono::steady_clock::now();
    occ.emplace(slam.occupancy());
    const double build_seconds = seconds_since(t0);
    std::vector<Eigen::Vector3d> path;
    for (const io::StampedPose& p : trajectory) path.push_back(p.pose.translation());
    occupancy::write_occupancy(*occ, slam.occupancy_params(), path, o.out);
    report.occupancy = occupancy_report(*occ);
    report.occupancy->build_seconds = build_seconds;
  }

  const fs::path folder = data_folder(o);
  if (folder.empty() || !fs::exists(folder / "scene.ply") || trajectory.size() < 2) return;
  try {
    const SceneTruth truth = load_scene_truth(trajectory, folder, camera, params.dense.max_depth);
    report.dense->map = evaluate_dense_map(cloud, truth);
    if (occ) report.occupancy->accuracy = evaluate_occupancy(occ->map, occ->grid, truth);
  } catch (const std::exception& e) {
    spdlog::warn("maps not judged: {}", e.what());
  }
}

}  // namespace lrd::runner
