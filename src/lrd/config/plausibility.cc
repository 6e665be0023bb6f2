#include "lrd/config/plausibility.h"

#include <fmt/format.h>

#include <cmath>

namespace lrd::config {

namespace {
// Written so that NaN fails every test.
bool within(double x, double lo, double hi) {
  return x >= lo && x <= hi;
}
bool positive_up_to(double x, double hi) {
  return x > 0.0 && x <= hi;
}
}  // namespace

std::optional<Implausible> implausible_camera(const camera::PinholeCamera& c) {
  constexpr int kMaxSide = 16384;  // as io::kMaxImageSide: no camera frame is larger
  if (c.width <= 0 || c.width > kMaxSide)
    return Implausible{"width", fmt::format("must be in [1, {}]", kMaxSide)};
  if (c.height <= 0 || c.height > kMaxSide)
    return Implausible{"height", fmt::format("must be in [1, {}]", kMaxSide)};
  if (!positive_up_to(c.fx, 1e5)) return Implausible{"fx", "must be in (0, 100000] pixels"};
  if (!positive_up_to(c.fy, 1e5)) return Implausible{"fy", "must be in (0, 100000] pixels"};
  // The principal point lies in or near the image for any real lens (a crop may move it out).
  if (!within(c.cx, -c.width, 2.0 * c.width))
    return Implausible{"cx", fmt::format("must be in [-width, 2 width] = [{}, {}]", -c.width, 2 * c.width)};
  if (!within(c.cy, -c.height, 2.0 * c.height))
    return Implausible{"cy",
                       fmt::format("must be in [-height, 2 height] = [{}, {}]", -c.height, 2 * c.height)};
  const std::pair<const char*, double> radial[] = {
      {"k1", c.distortion.k1}, {"k2", c.distortion.k2}, {"k3", c.distortion.k3}};
  for (const auto& [name, k] : radial)
    if (!within(k, -10.0, 10.0)) return Implausible{name, "must be in [-10, 10] (a pinhole lens)"};
  if (!within(c.distortion.p1, -1.0, 1.0)) return Implausible{"p1", "must be in [-1, 1]"};
  if (!within(c.distortion.p2, -1.0, 1.0)) return Implausible{"p2", "must be in [-1, 1]"};
  if (!positive_up_to(c.fps, 1000.0)) return Implausible{"fps", "must be in (0, 1000]"};
  if (!positive_up_to(c.bf, 1e5)) return Implausible{"bf", "must be in (0, 100000] (baseline x fx)"};
  if (!positive_up_to(c.th_depth, 1000.0)) return Implausible{"th_depth", "must be in (0, 1000] baselines"};
  if (!within(c.depth_map_factor, 1e-3, 1e6))
    return Implausible{"depth_map_factor", "must be in [0.001, 1e6]"};
  if (!positive_up_to(c.disparity_sigma, 100.0))
    return Implausible{"disparity_sigma", "must be in (0, 100] pixels"};
  // Rows are read out within one frame period (a negative time is no sensor's).
  if (!within(c.readout_time, 0.0, 1.0 / c.fps))
    return Implausible{"readout_time",
                       fmt::format("must be in [0, 1/fps] = [0, {:.4f}] seconds", 1.0 / c.fps)};
  return std::nullopt;
}

std::optional<Implausible> implausible_orb(const features::OrbParams& o) {
  if (o.n_features <= 0 || o.n_features > 100000) return Implausible{"n_features", "must be in [1, 100000]"};
  if (!(o.scale_factor > 1.0f && o.scale_factor <= 4.0f))
    return Implausible{"scale_factor", "must be in (1, 4]"};
  if (o.n_levels < 1 || o.n_levels > 32) return Implausible{"n_levels", "must be in [1, 32]"};
  if (o.ini_th_fast < 1 || o.ini_th_fast > 255) return Implausible{"ini_th_fast", "must be in [1, 255]"};
  if (o.min_th_fast < 1 || o.min_th_fast > o.ini_th_fast)
    return Implausible{"min_th_fast", "must be in [1, ini_th_fast]"};
  return std::nullopt;
}

}  // namespace lrd::config
