#include "lrd/node/map_messages.h"

#include <cstring>

namespace lrd::node {

std::vector<Eigen::Vector3d> frustum_lines(const Eigen::Isometry3d& T) {
  constexpr double w = 0.05, h = 0.0375, z = 0.04;
  const Eigen::Vector3d c = T.translation();
  const Eigen::Vector3d corners[4] = {T * Eigen::Vector3d(-w, -h, z), T * Eigen::Vector3d(w, -h, z),
                                      T * Eigen::Vector3d(w, h, z), T * Eigen::Vector3d(-w, h, z)};
  std::vector<Eigen::Vector3d> lines;
  lines.reserve(16);
  for (int i = 0; i < 4; ++i) {
    lines.push_back(c);
    lines.push_back(corners[i]);
    lines.push_back(corners[i]);
    lines.push_back(corners[(i + 1) % 4]);
  }
  return lines;
}

Eigen::Isometry3d grid_origin(const occupancy::Grid2d& grid) {
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  origin.linear() = grid.floor.rotation.transpose();
  origin.translation() = grid.floor.to_map(Eigen::Vector3d(grid.origin.x(), grid.origin.y(), 0.0));
  return origin;
}

namespace {

PackedCloud layout(std::size_t n, bool colour) {
  PackedCloud c;
  c.fields = {{"x", 0}, {"y", 4}, {"z", 8}};
  c.point_step = 16;
  if (colour) {
    c.fields.push_back({"rgb", 16});
    c.point_step = 32;
  }
  c.width = static_cast<std::uint32_t>(n);
  c.data.assign(n * c.point_step, 0);
  return c;
}

void put_xyz(PackedCloud& c, std::size_t i, float x, float y, float z) {
  const float xyz[3] = {x, y, z};
  std::memcpy(c.data.data() + i * c.point_step, xyz, sizeof xyz);
}

}  // namespace

PackedCloud pack_cloud(const dense::PointCloud& cloud) {
  const bool colour = cloud.colours.size() == cloud.points.size() && !cloud.points.empty();
  PackedCloud c = layout(cloud.size(), colour);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    put_xyz(c, i, cloud.points[i].x(), cloud.points[i].y(), cloud.points[i].z());
    if (!colour) continue;
    // rgb as PCL packs it: 0x00RRGGBB in a little-endian float32's bytes (B, G, R, 0).
    std::uint8_t* p = c.data.data() + i * c.point_step + 16;
    p[0] = cloud.colours[i][0];
    p[1] = cloud.colours[i][1];
    p[2] = cloud.colours[i][2];
  }
  return c;
}

PackedCloud pack_cloud(const std::vector<events::MapPointSnapshot>& points) {
  PackedCloud c = layout(points.size(), false);
  for (std::size_t i = 0; i < points.size(); ++i)
    put_xyz(c, i, static_cast<float>(points[i].position.x()), static_cast<float>(points[i].position.y()),
            static_cast<float>(points[i].position.z()));
  return c;
}

}  // namespace lrd::node
