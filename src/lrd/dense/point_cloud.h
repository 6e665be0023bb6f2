#pragma once
// A coloured point cloud (the dense map, the synthetic scene's surface samples).
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace lrd::dense {

struct PointCloud {
  std::vector<Eigen::Vector3f> points;
  std::vector<cv::Vec3b> colours;  // BGR, one per point (may be empty: no colour)
  [[nodiscard]] std::size_t size() const { return points.size(); }
};

}  // namespace lrd::dense
