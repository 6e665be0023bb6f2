#pragma once
// The floor under the map (docs/occupancy.md): where "up" is and how high the floor lies along it,
// so the 2-D grid can take the voxels between two heights above the floor. SLAM's map frame is the
// first camera's, with gravity unknown: the configured up (the camera's -y; cameras start roughly
// level) is refined to the normal of the dominant near-horizontal plane of the occupied voxels, and
// the floor is the lowest height along it that holds a large share of them (a table top holds
// fewer).
#include <Eigen/Core>
#include <optional>
#include <vector>

namespace lrd::occupancy {

struct FloorFrame {
  // Rows: the grid's x and y axes and up, in the map frame; floor frame = rotation * map frame.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  double height = 0.0;  // the floor along up from the map origin (m)
  [[nodiscard]] Eigen::Vector3d up() const { return rotation.row(2).transpose(); }
  // A map point in floor coordinates: x, y on the floor, z = height above it.
  [[nodiscard]] Eigen::Vector3d to_floor(const Eigen::Vector3d& p) const {
    Eigen::Vector3d q = rotation * p;
    q.z() -= height;
    return q;
  }
  [[nodiscard]] Eigen::Vector3d to_map(const Eigen::Vector3d& q) const {
    return rotation.transpose() * Eigen::Vector3d(q.x(), q.y(), q.z() + height);
  }
};

// The frame whose z is `up` (normalized), with the map's x axis projected on the floor as x.
[[nodiscard]] FloorFrame floor_frame(const Eigen::Vector3d& up, double height);

// From surface points (map frame): up is the direction within 30 deg of `up_hint` along which the
// points' heights pile up most sharply in 2 cm bins (horizontal surfaces: a coarse-to-fine search,
// 0.5 deg then 0.1 deg steps; walls spread evenly at every height and do not steer it), and the
// floor is the lowest pile holding >= 30 % of the largest one's points. `fixed_height` gives the
// floor instead (then up = up_hint). Fewer than 50 points: up_hint and the lowest point's height.
[[nodiscard]] FloorFrame estimate_floor(const std::vector<Eigen::Vector3d>& points,
                                        const Eigen::Vector3d& up_hint, std::optional<double> fixed_height);

}  // namespace lrd::occupancy
