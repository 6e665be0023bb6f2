#include "lrd/dynamic/depth_region_grower.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace lrd::dynamic {

cv::Mat grow_regions(const cv::Mat& depth, const std::vector<RegionSeed>& seeds, double fx, double fy,
                     const RegionGrowParams& params) {
  const int w = depth.cols / 2, h = depth.rows / 2;
  cv::Mat half(h, w, CV_32FC1);
  for (int y = 0; y < h; ++y) {
    const float* src = depth.ptr<float>(2 * y);
    float* dst = half.ptr<float>(y);
    for (int x = 0; x < w; ++x) dst[x] = src[2 * x];
  }
  cv::Mat region = cv::Mat::zeros(h, w, CV_8UC1);
  const double fx_h = fx / 2.0, fy_h = fy / 2.0;
  std::vector<cv::Point> queue;
  for (const RegionSeed& s : seeds) {
    const int u0 = std::clamp(static_cast<int>(s.u / 2.0f), 0, w - 1);
    const int v0 = std::clamp(static_cast<int>(s.v / 2.0f), 0, h - 1);
    if (region.at<std::uint8_t>(v0, u0) != 0) continue;
    const double d0 = half.at<float>(v0, u0) > 0.0f ? half.at<float>(v0, u0) : s.depth;
    if (d0 <= 0.0) continue;
    region.at<std::uint8_t>(v0, u0) = 255;
    queue.assign(1, cv::Point(u0, v0));
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const cv::Point p = queue[head];
      const double dp = half.at<float>(p.y, p.x) > 0.0f ? half.at<float>(p.y, p.x) : d0;
      static constexpr int kDx[4] = {1, -1, 0, 0}, kDy[4] = {0, 0, 1, -1};
      for (int k = 0; k < 4; ++k) {
        const int x = p.x + kDx[k], y = p.y + kDy[k];
        if (x < 0 || y < 0 || x >= w || y >= h || region.at<std::uint8_t>(y, x) != 0) continue;
        const double d = half.at<float>(y, x);
        if (d <= 0.0) continue;
        if (std::abs(d - dp) > params.step + 0.01 * dp || std::abs(d - d0) > params.band) continue;
        if (std::abs(x - u0) * d / fx_h > params.extent || std::abs(y - v0) * d / fy_h > 1.5 * params.extent)
          continue;
        region.at<std::uint8_t>(y, x) = 255;
        queue.emplace_back(x, y);
      }
    }
  }
  cv::Mat full;
  cv::resize(region, full, depth.size(), 0, 0, cv::INTER_NEAREST);
  return full;
}

}  // namespace lrd::dynamic
