#include "lrd/dense/voxel_grid.h"

#include "lrd/dense/voxel_key.h"

namespace lrd::dense {

VoxelGrid::VoxelGrid(double voxel_size) : inv_size_(1.0 / voxel_size) {}

void VoxelGrid::reserve(std::size_t voxels) {
  index_.reserve(voxels);
  cells_.reserve(voxels);
}

void VoxelGrid::add(const Eigen::Vector3f& p, const cv::Vec3b& bgr) {
  if (!p.allFinite()) return;
  const auto [it, inserted] =
      index_.try_emplace(voxel_key(p, inv_size_), static_cast<std::uint32_t>(cells_.size()));
  if (inserted) cells_.emplace_back();
  Cell& c = cells_[it->second];
  c.sum += p.cast<double>();
  c.b += bgr[0];
  c.g += bgr[1];
  c.r += bgr[2];
  ++c.count;
}

void VoxelGrid::add(const PointCloud& cloud) {
  const bool coloured = cloud.colours.size() == cloud.points.size();
  for (std::size_t i = 0; i < cloud.points.size(); ++i)
    add(cloud.points[i], coloured ? cloud.colours[i] : cv::Vec3b(255, 255, 255));
}

PointCloud VoxelGrid::cloud() const {
  PointCloud out;
  out.points.reserve(cells_.size());
  out.colours.reserve(cells_.size());
  for (const Cell& c : cells_) {
    const double n = c.count;
    out.points.push_back((c.sum / n).cast<float>());
    const auto mean = [&](std::uint32_t s) {
      return static_cast<unsigned char>((s + c.count / 2) / c.count);
    };
    out.colours.emplace_back(mean(c.b), mean(c.g), mean(c.r));
  }
  return out;
}

}  // namespace lrd::dense
