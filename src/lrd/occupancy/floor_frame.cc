#include "lrd/occupancy/floor_frame.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

namespace lrd::occupancy {

FloorFrame floor_frame(const Eigen::Vector3d& up_in, double height) {
  const Eigen::Vector3d up = up_in.normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - up * up.x();
  if (x.norm() < 1e-3) x = Eigen::Vector3d::UnitZ() - up * up.z();
  x.normalize();
  FloorFrame f;
  f.rotation.row(0) = x.transpose();
  f.rotation.row(1) = up.cross(x).transpose();
  f.rotation.row(2) = up.transpose();
  f.height = height;
  return f;
}

namespace {
constexpr double kBin = 0.02;  // m: height bins

// Point heights along `up` in kBin bins (index 0 at -extent).
std::vector<std::uint32_t> height_histogram(const std::vector<Eigen::Vector3d>& pts,
                                            const Eigen::Vector3d& up, double extent) {
  std::vector<std::uint32_t> bins(static_cast<std::size_t>(2.0 * extent / kBin) + 2, 0);
  for (const Eigen::Vector3d& p : pts) {
    const auto b = static_cast<long>(std::floor((up.dot(p) + extent) / kBin));
    if (b >= 0 && b < static_cast<long>(bins.size())) ++bins[static_cast<std::size_t>(b)];
  }
  return bins;
}

// How sharply the heights pile up: the fullest window of two bins.
std::uint32_t sharpness(const std::vector<std::uint32_t>& bins) {
  std::uint32_t best = 0;
  for (std::size_t i = 0; i + 1 < bins.size(); ++i) best = std::max(best, bins[i] + bins[i + 1]);
  return best;
}

// The best of the directions hint + tan(a) e1 + tan(b) e2, a and b in [-span, span] by `step`.
// The steps must be fine: 4 m of floor 1 deg off spreads over 7 cm, and a small table top, level
// or not, then outscores it (2 deg steps found walking_loop's up 1.2 deg off, its floor 40 cm high).
Eigen::Vector3d search_up(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& hint,
                          double span_deg, double step_deg, double extent) {
  const FloorFrame axes = floor_frame(hint, 0.0);
  const Eigen::Vector3d e1 = axes.rotation.row(0), e2 = axes.rotation.row(1);
  const int n = static_cast<int>(std::lround(span_deg / step_deg));
  Eigen::Vector3d best = hint;
  std::uint32_t best_score = 0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j) {
      const double a = i * step_deg * M_PI / 180.0, b = j * step_deg * M_PI / 180.0;
      const Eigen::Vector3d up = (hint + std::tan(a) * e1 + std::tan(b) * e2).normalized();
      const std::uint32_t score = sharpness(height_histogram(pts, up, extent));
      if (score > best_score) {
        best_score = score;
        best = up;
      }
    }
  return best;
}
}  // namespace

FloorFrame estimate_floor(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up_hint,
                          std::optional<double> fixed_height) {
  const Eigen::Vector3d hint = up_hint.normalized();
  if (fixed_height) return floor_frame(hint, *fixed_height);
  if (points.size() < 50) {
    double lowest = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i)
      lowest = i == 0 ? hint.dot(points[i]) : std::min(lowest, hint.dot(points[i]));
    return floor_frame(hint, lowest);
  }
  // The coarse search on at most 5000 points, the fine one on 20000, the floor's height from all.
  const auto every = [&](std::size_t most) {
    std::vector<Eigen::Vector3d> sample;
    const std::size_t stride = std::max<std::size_t>(1, points.size() / most);
    for (std::size_t i = 0; i < points.size(); i += stride) sample.push_back(points[i]);
    return sample;
  };
  double extent = 0.0;
  for (const Eigen::Vector3d& p : points) extent = std::max(extent, p.norm());
  extent += kBin;
  Eigen::Vector3d up = search_up(every(5000), hint, 30.0, 0.5, extent);
  up = search_up(every(20000), up, 0.5, 0.1, extent);
  // The lowest local maximum (two-bin windows) with >= 30 % of the fullest window.
  const std::vector<std::uint32_t> bins = height_histogram(points, up, extent);
  std::vector<std::uint32_t> window(bins.size(), 0);
  for (std::size_t i = 0; i + 1 < bins.size(); ++i) window[i] = bins[i] + bins[i + 1];
  const std::uint32_t most = *std::max_element(window.begin(), window.end());
  std::size_t floor_bin = 0;
  for (std::size_t i = 0; i < window.size(); ++i) {
    const bool peak =
        (i == 0 || window[i] >= window[i - 1]) && (i + 1 == window.size() || window[i] >= window[i + 1]);
    if (peak && window[i] * 10 >= most * 3) {
      floor_bin = i;
      break;
    }
  }
  // Its height: the median of the points in the window.
  std::vector<double> near;
  const double low = static_cast<double>(floor_bin) * kBin - extent, high = low + 2.0 * kBin;
  for (const Eigen::Vector3d& p : points)
    if (const double h = up.dot(p); h >= low && h < high) near.push_back(h);
  std::nth_element(near.begin(), near.begin() + static_cast<long>(near.size() / 2), near.end());
  return floor_frame(up, near[near.size() / 2]);
}

}  // namespace lrd::occupancy
