#pragma once
// PLY point clouds: written as binary little-endian (float x y z, uchar red green blue), which
// Open3D, CloudCompare, PCL and MeshLab read; read from binary little-endian or ASCII PLY with
// float or double coordinates (other vertex properties and elements are skipped).
#include <filesystem>

#include "lrd/dense/point_cloud.h"

namespace lrd::dense {

// Throws lrd::Error naming the file when it cannot be written.
void write_ply(const std::filesystem::path& file, const PointCloud& cloud);
// Throws lrd::Error naming the file for a missing, truncated or unsupported file.
[[nodiscard]] PointCloud read_ply(const std::filesystem::path& file);

}  // namespace lrd::dense
