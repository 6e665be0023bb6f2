#include "lrd/tracking/view_coverage.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "lrd/map/map_point.h"

namespace lrd::tracking {
namespace {

// Spread of `values` between their 5th and 95th percentiles (reorders them).
float percentile_extent(std::vector<float>& values) {
  const std::size_t n = values.size();
  const auto lo = static_cast<std::ptrdiff_t>(n / 20), hi = static_cast<std::ptrdiff_t>(n - 1 - n / 20);
  std::nth_element(values.begin(), values.begin() + lo, values.end());
  const float low = values[static_cast<std::size_t>(lo)];
  std::nth_element(values.begin(), values.begin() + hi, values.end());
  return values[static_cast<std::size_t>(hi)] - low;
}

double extent_ratio(std::vector<float>& part, std::vector<float>& whole) {
  const float w = percentile_extent(whole);
  return w > 0.0f ? percentile_extent(part) / w : 1.0;
}

}  // namespace

double tracked_view_coverage(const data::Frame& frame) {
  std::vector<float> all_u, all_v, tracked_u, tracked_v;
  for (auto* v : {&all_u, &all_v, &tracked_u, &tracked_v}) v->reserve(frame.size());
  for (std::size_t i = 0; i < frame.size(); ++i) {
    if (!frame.is_close(i)) continue;
    const cv::Point2f& pt = frame.undistorted()[i].pt;
    all_u.push_back(pt.x);
    all_v.push_back(pt.y);
    if (frame.map_points[i] != nullptr && !frame.outliers[i]) {
      tracked_u.push_back(pt.x);
      tracked_v.push_back(pt.y);
    }
  }
  if (tracked_u.size() < 10) return 1.0;
  return std::min(extent_ratio(tracked_u, all_u), extent_ratio(tracked_v, all_v));
}

}  // namespace lrd::tracking

namespace lrd::tracking {

int reference_points_hidden(const data::Frame& frame, const map::KeyFrame& reference, int min_observations) {
  const cv::Mat& mask = frame.dynamic_mask;
  if (mask.empty() || !frame.has_pose()) return 0;
  const camera::PinholeCamera& cam = frame.camera();
  const Eigen::Isometry3d& T_cw = frame.T_cw();
  int hidden = 0;
  for (const map::MapPoint* mp : reference.map_points()) {
    if (mp == nullptr || mp->is_bad() || mp->num_observations() < min_observations) continue;
    const Eigen::Vector3d p_c = T_cw * mp->position();
    if (p_c.z() <= 0.0) continue;
    // The mask is in image pixels; the undistorted projection is within the mask's dilation of
    // them on the cameras we meet (and equal without distortion).
    const Eigen::Vector2d uv = cam.project(p_c);
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    if (u < 0 || v < 0 || u >= mask.cols || v >= mask.rows) continue;
    hidden += mask.at<std::uint8_t>(v, u) != 0 ? 1 : 0;
  }
  return hidden;
}

}  // namespace lrd::tracking
