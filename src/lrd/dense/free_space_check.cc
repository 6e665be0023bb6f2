#include "lrd/dense/free_space_check.h"

#include <cmath>

namespace lrd::dense {

void vote_free_space(const PointCloud& cloud, const Eigen::Isometry3d& T_cw_cloud, const RgbdView& view,
                     const camera::PinholeCamera& camera, const FreeSpaceParams& params,
                     std::vector<std::uint8_t>& votes) {
  const Eigen::Isometry3f T = (view.T_cw * T_cw_cloud.inverse()).cast<float>();
  const auto margin = static_cast<float>(params.margin), ratio = static_cast<float>(params.margin_ratio);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f p = T * cloud.points[i];
    if (p.z() < 0.1f) continue;
    const int u = static_cast<int>(std::lround(camera.fx * p.x() / p.z() + camera.cx));
    const int v = static_cast<int>(std::lround(camera.fy * p.y() / p.z() + camera.cy));
    if (u < 0 || v < 0 || u >= view.depth.cols || v >= view.depth.rows) continue;
    if (!view.dynamic.empty() && view.dynamic.at<unsigned char>(v, u) != 0) continue;
    const float z = view.depth.at<float>(v, u);
    if (z > 0.0f && z > p.z() + margin + ratio * p.z() && votes[i] < 255) ++votes[i];
  }
}

}  // namespace lrd::dense
