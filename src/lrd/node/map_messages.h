#pragma once
// The content of the nodes' map messages, whatever their ROS: keyframes as camera frustums (a
// visualization_msgs LINE_LIST), the occupancy grid's origin pose, and point clouds packed as
// sensor_msgs/PointCloud2 lays them out (x y z float32, and rgb packed into a float32, padded to
// 16 and 32 bytes a point as ROS 1's PointCloud2Modifier does).
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "lrd/dense/point_cloud.h"
#include "lrd/events/map_snapshot.h"
#include "lrd/occupancy/grid_2d.h"

namespace lrd::node {

inline constexpr double kKeyframeLineWidth = 0.005;  // m

// A keyframe (camera pose in the map) as a small frustum: 16 points, pairs of line ends.
[[nodiscard]] std::vector<Eigen::Vector3d> frustum_lines(const Eigen::Isometry3d& T_map_camera);

// Cell (0, 0)'s corner on the floor, the grid's axes along the floor: the floor frame in the map
// frame (whose axes are the first camera's, not z-up). nav_msgs/MapMetaData's origin.
[[nodiscard]] Eigen::Isometry3d grid_origin(const occupancy::Grid2d& grid);

// sensor_msgs/PointField's datatype FLOAT32.
inline constexpr std::uint8_t kPointFieldFloat32 = 7;

struct CloudField {
  std::string name;
  std::uint32_t offset = 0;
};

// A cloud as PointCloud2 carries it: one row of `width` points, little-endian, dense.
struct PackedCloud {
  std::vector<CloudField> fields;  // FLOAT32, count 1 each
  std::uint32_t point_step = 0;
  std::uint32_t width = 0;
  std::vector<std::uint8_t> data;
};

[[nodiscard]] PackedCloud pack_cloud(const dense::PointCloud& cloud);
[[nodiscard]] PackedCloud pack_cloud(const std::vector<events::MapPointSnapshot>& points);

}  // namespace lrd::node
