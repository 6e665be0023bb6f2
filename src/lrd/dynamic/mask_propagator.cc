#include "lrd/dynamic/mask_propagator.h"

#include <opencv2/imgproc.hpp>

namespace lrd::dynamic {

cv::Mat propagate_mask(const cv::Mat& mask, const cv::Mat& depth, const Eigen::Isometry3d& T_t_k,
                       const camera::PinholeCamera& camera) {
  cv::Mat out = cv::Mat::zeros(mask.size(), CV_8UC1);
  // Without a usable depth image every pixel stays where it was.
  const bool has_depth = !depth.empty() && depth.type() == CV_32FC1 && depth.size() == mask.size();
  const Eigen::Matrix3d R = T_t_k.linear();
  const Eigen::Vector3d t = T_t_k.translation();
  const double ifx = 1.0 / camera.fx, ify = 1.0 / camera.fy;
  for (int v = 0; v < mask.rows; ++v) {
    const auto* m = mask.ptr<std::uint8_t>(v);
    const float* d = has_depth ? depth.ptr<float>(v) : nullptr;
    for (int u = 0; u < mask.cols; ++u) {
      if (m[u] == 0) continue;
      int ut = u, vt = v;
      if (d != nullptr && d[u] > 0.0f) {
        const Eigen::Vector3d p((u - camera.cx) * ifx * d[u], (v - camera.cy) * ify * d[u], d[u]);
        const Eigen::Vector3d q = R * p + t;
        if (q.z() <= 0.05) continue;
        ut = static_cast<int>(std::lround(camera.fx * q.x() / q.z() + camera.cx));
        vt = static_cast<int>(std::lround(camera.fy * q.y() / q.z() + camera.cy));
      }
      // A 2x2 splat closes the holes a forward warp leaves when the object comes closer.
      for (int dv = 0; dv < 2; ++dv)
        for (int du = 0; du < 2; ++du) {
          const int x = ut + du, y = vt + dv;
          if (x >= 0 && y >= 0 && x < out.cols && y < out.rows) out.at<std::uint8_t>(y, x) = 255;
        }
    }
  }
  return out;
}

void dilate_mask(cv::Mat& mask, int radius) {
  if (radius <= 0 || mask.empty()) return;
  if (radius < 12) {
    const cv::Mat disc = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
    cv::dilate(mask, mask, disc);
    return;
  }
  // Large radii (async masks grow with age) at half resolution: a disc's cost grows with its
  // size, and a mask this wide does not need single-pixel precision (measured: radius 31 on
  // 640x480 took ~15 ms at full resolution).
  cv::Mat half;
  cv::resize(mask, half, cv::Size((mask.cols + 1) / 2, (mask.rows + 1) / 2), 0, 0, cv::INTER_AREA);
  half = half > 0;  // any masked pixel of a 2x2 block marks the block
  const int r = (radius + 1) / 2 + 1;  // covers the full-resolution disc despite the 2x2 blocks
  const cv::Mat disc = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
  cv::dilate(half, half, disc);
  cv::Mat full;
  cv::resize(half, full, mask.size(), 0, 0, cv::INTER_NEAREST);
  cv::bitwise_or(mask, full, mask);
}

}  // namespace lrd::dynamic
