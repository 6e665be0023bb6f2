#pragma once
// Voxel downsampling with a hash of occupied voxels: one point per voxel, the mean of the points
// (and colours) that fell into it. Chosen over PCL's VoxelGrid / Open3D (docs/dense-map.md): the
// map needs only this, and those packages would add hundreds of MB of dependencies.
// Output order is the order in which voxels were first hit, so identical input gives identical
// output.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "lrd/dense/point_cloud.h"

namespace lrd::dense {

class VoxelGrid {
 public:
  explicit VoxelGrid(double voxel_size);

  // Non-finite points are ignored.
  void add(const Eigen::Vector3f& p, const cv::Vec3b& bgr);
  void add(const PointCloud& cloud);
  [[nodiscard]] std::size_t size() const { return cells_.size(); }
  [[nodiscard]] PointCloud cloud() const;
  void reserve(std::size_t voxels);

 private:
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    std::uint32_t b = 0, g = 0, r = 0, count = 0;
  };
  double inv_size_;
  std::unordered_map<std::uint64_t, std::uint32_t> index_;
  std::vector<Cell> cells_;
};

}  // namespace lrd::dense
