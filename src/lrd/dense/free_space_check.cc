#include "lrd/dense/free_space_check.h"

#include <cmath>

namespace lrd::dense {

RgbdView coarse_view(const RgbdView& view, int factor) {
  RgbdView c;
  c.T_cw = view.T_cw;
  const int w = view.depth.cols / factor, h = view.depth.rows / factor;
  c.depth = cv::Mat(h, w, CV_32F, cv::Scalar(0));
  c.dynamic = cv::Mat(h, w, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float nearest = 0.0f;
      bool dynamic = false;
      for (int dy = 0; dy < factor; ++dy) {
        const float* z = view.depth.ptr<float>(y * factor + dy) + x * factor;
        const unsigned char* m =
            view.dynamic.empty() ? nullptr : view.dynamic.ptr<unsigned char>(y * factor + dy) + x * factor;
        for (int dx = 0; dx < factor; ++dx) {
          if (z[dx] > 0.0f && (nearest == 0.0f || z[dx] < nearest)) nearest = z[dx];  // NaN fails z > 0
          dynamic = dynamic || (m != nullptr && m[dx] != 0);
        }
      }
      c.depth.at<float>(y, x) = nearest;
      c.dynamic.at<unsigned char>(y, x) = dynamic ? 255 : 0;
    }
  return c;
}

camera::PinholeCamera coarse_camera(const camera::PinholeCamera& camera, int factor) {
  camera::PinholeCamera c = camera;
  const double f = factor;
  c.fx /= f;
  c.fy /= f;
  c.cx = (camera.cx + 0.5) / f - 0.5;  // pixel centres
  c.cy = (camera.cy + 0.5) / f - 0.5;
  c.width = camera.width / factor;
  c.height = camera.height / factor;
  return c;
}

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
