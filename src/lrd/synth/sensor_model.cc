#include "lrd/synth/sensor_model.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace lrd::synth {

SensorModel::SensorModel(const camera::PinholeCamera& camera, SensorParams params, std::uint64_t seed)
    : cam_(camera), params_(params), noise_(seed) {}

cv::Mat SensorModel::depth_image(const RenderBuffers& ideal, int frame) const {
  const int W = ideal.depth.cols, H = ideal.depth.rows;
  const double fb = cam_.fx * params_.baseline;
  const auto noise = noise_.gaussian(frame, 1), drop = noise_.uniform(frame, 2);
  cv::Mat out(H, W, CV_16U, cv::Scalar(0));
  for (int y = 0; y < H; ++y) {
    const float* z = ideal.depth.ptr<float>(y);
    const float* inc = ideal.incidence.ptr<float>(y);
    const float* z_up = ideal.depth.ptr<float>(std::max(0, y - 1));
    const float* z_dn = ideal.depth.ptr<float>(std::min(H - 1, y + 1));
    auto* o = out.ptr<std::uint16_t>(y);
    // Projector shadows: a surface point is lit only if its projector column x + d(x) exceeds
    // that of every point to its left on the row (structured-light ordering).
    double max_projector_x = -std::numeric_limits<double>::infinity();
    for (int x = 0; x < W; ++x) {
      const double zi = z[x];
      if (zi <= 0.0) continue;
      const double d = fb / zi;
      const double px = x + d;
      const bool shadowed = px < max_projector_x - 0.5;
      max_projector_x = std::max(max_projector_x, px);
      if (shadowed || zi < params_.min_depth || zi > params_.max_depth) continue;
      const auto idx =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x);
      // Grazing incidence: the speckle pattern smears and the sensor reports nothing.
      const double c = inc[x];
      if (c < params_.grazing_cos_invalid) continue;
      if (c < params_.grazing_cos_random &&
          drop(idx) <
              (params_.grazing_cos_random - c) / (params_.grazing_cos_random - params_.grazing_cos_invalid))
        continue;
      // Depth edges: pixels next to a jump of more than ~5 % drop out at random (flying pixels).
      const double zl = z[std::max(0, x - 1)], zr = z[std::min(W - 1, x + 1)];
      const double jump =
          std::max({std::abs(zl - zi), std::abs(zr - zi), std::abs(z_up[x] - zi), std::abs(z_dn[x] - zi)});
      if (jump > 0.05 * zi && drop(idx + 7919) < params_.edge_dropout) continue;
      double dn = d + params_.disparity_sigma * noise(idx);
      dn = std::round(dn / params_.disparity_step) * params_.disparity_step;
      if (dn <= 0.0) continue;
      const double zm = fb / dn;
      if (zm > params_.max_depth) continue;
      o[x] = cv::saturate_cast<std::uint16_t>(std::lround(zm * cam_.depth_map_factor));
    }
  }
  return out;
}

cv::Mat SensorModel::rgb_image(const cv::Mat& ideal_bgr, int frame) const {
  cv::Mat blurred;
  cv::GaussianBlur(ideal_bgr, blurred, cv::Size(5, 5), params_.rgb_blur_sigma, params_.rgb_blur_sigma,
                   cv::BORDER_REFLECT101);
  const auto noise = noise_.gaussian(frame, 3);
  const int W = blurred.cols;
  const auto sigma = static_cast<float>(params_.rgb_noise_sigma);
  for (int y = 0; y < blurred.rows; ++y) {
    auto* p = blurred.ptr<std::uint8_t>(y);
    for (int i = 0; i < 3 * W; ++i) {
      const auto idx =
          static_cast<std::size_t>(y) * 3u * static_cast<std::size_t>(W) + static_cast<std::size_t>(i);
      p[i] = cv::saturate_cast<std::uint8_t>(static_cast<float>(p[i]) + sigma * noise(idx));
    }
  }
  return blurred;
}

}  // namespace lrd::synth
