#include "lrd/occupancy/occupancy_builder.h"

#include <algorithm>

#include "lrd/dense/voxel_grid.h"

namespace lrd::occupancy {

OccupancyMap build_occupancy_map(const std::vector<dense::DenseMapper::KeyframeCloud>& clouds,
                                 const OccupancyParams& params) {
  OccupancyMap map(params);
  RayBundle rays;
  for (const dense::DenseMapper::KeyframeCloud& c : clouds) {
    const dense::PointCloud& local = *c.local;
    const Eigen::Isometry3f T = c.T_wc.cast<float>();
    rays.origin = c.T_wc.translation();
    rays.points.resize(local.size());
    rays.depth.resize(local.size());
    rays.hit.assign(c.kept.begin(), c.kept.end());
    rays.timestamp = c.timestamp;
    rays.trusted = c.trusted;
    rays.measured = c.measured;
    for (std::size_t k = 0; k < local.size(); ++k) {
      rays.points[k] = T * local.points[k];
      rays.depth[k] = local.points[k].z();
    }
    map.integrate(rays);
  }
  return map;
}

namespace {
// The surfaces the map keeps, once each (2 cm voxels; a surface seen by many keyframes would
// otherwise count many times and a close table outweigh the floor), in the map frame. The floor is
// fitted to them rather than to voxel centres (a tilted floor's voxels are a staircase).
std::vector<Eigen::Vector3d> surface_sample(const std::vector<dense::DenseMapper::KeyframeCloud>& clouds) {
  dense::VoxelGrid grid(0.02);
  for (const auto& c : clouds) {
    const Eigen::Isometry3f T = c.T_wc.cast<float>();
    for (std::size_t k = 0; k < c.local->size(); ++k)
      if (c.kept[k]) grid.add(T * c.local->points[k], c.local->colours[k]);
  }
  const dense::PointCloud unique = grid.cloud();
  std::vector<Eigen::Vector3d> out;
  out.reserve(unique.size());
  for (const Eigen::Vector3f& p : unique.points) out.push_back(p.cast<double>());
  return out;
}
}  // namespace

Occupancy build_occupancy(const std::vector<dense::DenseMapper::KeyframeCloud>& clouds,
                          const OccupancyParams& params) {
  Occupancy o{build_occupancy_map(clouds, params), {}, {}};
  o.floor = estimate_floor(surface_sample(clouds), params.up, params.floor_height);
  o.grid = project_to_grid(o.map, o.floor, params.min_height, params.max_height, params.filter_speckles);
  return o;
}

void write_occupancy(const Occupancy& occupancy, const OccupancyParams& params,
                     const std::vector<Eigen::Vector3d>& camera_path, const std::filesystem::path& out) {
  occupancy.map.write_binary(out / "occupancy.bt");
  write_map_server(occupancy.grid, out, "occupancy_2d", {params.occupied_thresh, params.free_thresh});
  write_grid_picture(occupancy.grid, camera_path, out / "occupancy_2d.png");
}

}  // namespace lrd::occupancy
