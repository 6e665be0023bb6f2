#include "lrd/tracking/view_coverage.h"

#include <algorithm>
#include <cstddef>
#include <vector>

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
