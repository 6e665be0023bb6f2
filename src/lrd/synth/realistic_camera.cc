#include "lrd/synth/realistic_camera.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "lrd/features/keypoint_undistorter.h"

namespace lrd::synth {
namespace {

constexpr double kGamma = 2.2;
// Noise streams (SensorModel uses 1-3).
constexpr std::uint64_t kShotStream = 21, kReadStream = 22, kHoleStream = 23;

// For every pixel of the distorted image, the pinhole pixel it shows (the tracker's keypoint
// undistortion, iterated to convergence), shifted by `shift` in the distorted image first.
void distortion_maps(const camera::PinholeCamera& cam, const camera::Distortion& d, cv::Point2f shift,
                     cv::Mat& map_x, cv::Mat& map_y) {
  std::vector<cv::KeyPoint> pixels;
  pixels.reserve(static_cast<std::size_t>(cam.width) * static_cast<std::size_t>(cam.height));
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x)
      pixels.emplace_back(static_cast<float>(x) + shift.x, static_cast<float>(y) + shift.y, 1.0f);
  camera::PinholeCamera lens = cam;
  lens.distortion = d;
  const std::vector<cv::KeyPoint> ideal = features::KeypointUndistorter(lens).undistort(pixels);
  map_x.create(cam.height, cam.width, CV_32F);
  map_y.create(cam.height, cam.width, CV_32F);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const cv::Point2f& p = ideal[static_cast<std::size_t>(y) * static_cast<std::size_t>(cam.width) +
                                   static_cast<std::size_t>(x)]
                                 .pt;
      map_x.at<float>(y, x) = p.x;
      map_y.at<float>(y, x) = p.y;
    }
}

}  // namespace

RealisticCamera::RealisticCamera(const camera::PinholeCamera& truth, RealismParams params,
                                 double optics_blur_sigma, const NoiseTable& noise)
    : truth_(truth), params_(std::move(params)), optics_blur_sigma_(optics_blur_sigma), noise_(noise) {
  const camera::Distortion none{};
  const camera::Distortion& lens = params_.distortion ? params_.rendered_distortion : none;
  distortion_maps(truth_, lens, {0.0f, 0.0f}, distort_x_, distort_y_);
  if (params_.depth_registration) {
    distortion_maps(truth_, lens,
                    cv::Point2f(static_cast<float>(params_.registration_error_x),
                                static_cast<float>(params_.registration_error_y)),
                    depth_x_, depth_y_);
  } else {
    depth_x_ = distort_x_;  // the same maps, shared
    depth_y_ = distort_y_;
  }
  // Vignetting: a radial fall-off, 1 at the principal point, 1 - loss at the farthest corner.
  vignette_.create(truth_.height, truth_.width, CV_32F);
  const double r_corner =
      std::max({std::hypot(truth_.cx, truth_.cy), std::hypot(truth_.width - truth_.cx, truth_.cy),
                std::hypot(truth_.cx, truth_.height - truth_.cy),
                std::hypot(truth_.width - truth_.cx, truth_.height - truth_.cy)});
  const double loss = params_.vignetting ? params_.vignetting_corner_loss : 0.0;
  for (int y = 0; y < truth_.height; ++y)
    for (int x = 0; x < truth_.width; ++x) {
      const double r = std::hypot(x - truth_.cx, y - truth_.cy) / r_corner;
      vignette_.at<float>(y, x) = static_cast<float>(1.0 - loss * r * r);
    }
  to_linear_.resize(256);
  for (int v = 0; v < 256; ++v)
    to_linear_[static_cast<std::size_t>(v)] = static_cast<float>(std::pow(v / 255.0, kGamma));
}

RealisticCamera::Exposure RealisticCamera::expose(const cv::Mat& bgr) const {
  // The view's mean linear colour, on every 4th pixel of every 4th row.
  cv::Vec3d mean(0, 0, 0);
  int n = 0;
  for (int y = 0; y < bgr.rows; y += 4) {
    const auto* p = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; x += 4, ++n)
      for (int c = 0; c < 3; ++c) mean[c] += to_linear_[p[x][c]];
  }
  mean /= std::max(1, n);
  Exposure e;
  e.time = params_.reference_exposure;
  const double grey = std::max(1e-6, (mean[0] + mean[1] + mean[2]) / 3.0);
  if (params_.auto_exposure) {
    // Exposure time first (no noise cost), then gain for what the longest exposure cannot give.
    const double target = std::pow(params_.target_grey / 255.0, kGamma);
    e.time =
        std::clamp(params_.reference_exposure * target / grey, params_.min_exposure, params_.max_exposure);
    e.gain = std::clamp(target / (grey * e.time / params_.reference_exposure), 1.0, params_.max_gain);
  }
  if (params_.white_balance) {
    // Part-way grey world, the gains' geometric mean kept at 1.
    double log_sum = 0.0;
    for (int c = 0; c < 3; ++c) {
      e.white_balance[c] = std::pow(grey / std::max(1e-6, mean[c]), params_.white_balance_strength);
      log_sum += std::log(e.white_balance[c]);
    }
    for (int c = 0; c < 3; ++c) e.white_balance[c] /= std::exp(log_sum / 3.0);
  }
  return e;
}

RealisticCamera::ShutterPlan RealisticCamera::shutter(double t, const Exposure& exposure) const {
  const int H = truth_.height;
  const double readout = params_.rolling_shutter ? params_.readout_time : 0.0;
  const double width = params_.motion_blur ? exposure.time : 0.0;
  const double t0 = t - 0.5 * (readout + width), t1 = t + 0.5 * (readout + width);
  ShutterPlan plan;
  // An odd count, so the middle instant is the frame's own and its render is reused.
  int n = 1;
  if (t1 - t0 >= 1e-9) {
    n = std::clamp(static_cast<int>(std::ceil((t1 - t0) / params_.subframe_spacing)) + 1, 3,
                   std::max(3, params_.max_subframes));
    if (n % 2 == 0) --n;
  }
  for (int k = 0; k < n; ++k) plan.times.push_back(2 * k == n - 1 ? t : t0 + (t1 - t0) * k / (n - 1));
  plan.row_weights = cv::Mat(H, n, CV_32F, cv::Scalar(0));
  // Light between two renders is taken as varying linearly; a row's exposure window is averaged
  // over 16 points of it.
  constexpr int kPoints = 16;
  for (int y = 0; y < H; ++y) {
    auto* w = plan.row_weights.ptr<float>(y);
    if (n == 1) {
      w[0] = 1.0f;
      continue;
    }
    const double centre = t + readout * (H > 1 ? static_cast<double>(y) / (H - 1) - 0.5 : 0.0);
    for (int j = 0; j < kPoints; ++j) {
      const double s = centre + width * ((j + 0.5) / kPoints - 0.5);
      const double u = std::clamp((s - t0) / (t1 - t0) * (n - 1), 0.0, static_cast<double>(n - 1));
      const int k = std::min(n - 2, static_cast<int>(u));
      const double f = u - k;
      w[k] += static_cast<float>((1.0 - f) / kPoints);
      w[k + 1] += static_cast<float>(f / kPoints);
    }
  }
  return plan;
}

cv::Mat RealisticCamera::linear(const cv::Mat& bgr) const {
  cv::Mat out(bgr.size(), CV_32FC3);
  for (int y = 0; y < bgr.rows; ++y) {
    const auto* p = bgr.ptr<std::uint8_t>(y);
    auto* o = out.ptr<float>(y);
    for (int i = 0; i < 3 * bgr.cols; ++i) o[i] = to_linear_[p[i]];
  }
  return out;
}

cv::Mat RealisticCamera::integrate(const std::vector<cv::Mat>& renders, const ShutterPlan& plan) const {
  if (renders.size() == 1) return linear(renders.front());
  cv::Mat out(renders.front().size(), CV_32FC3, cv::Scalar::all(0));
  for (int y = 0; y < out.rows; ++y) {
    auto* o = out.ptr<float>(y);
    const auto* w = plan.row_weights.ptr<float>(y);
    for (std::size_t k = 0; k < renders.size(); ++k) {
      if (w[k] == 0.0f) continue;
      const auto* p = renders[k].ptr<std::uint8_t>(y);
      for (int i = 0; i < 3 * out.cols; ++i) o[i] += w[k] * to_linear_[p[i]];
    }
  }
  return out;
}

cv::Mat RealisticCamera::develop(const cv::Mat& linear_bgr, const Exposure& exposure, int frame) const {
  // The lens: distortion (the pinhole render resampled) and its blur.
  cv::Mat light;
  if (params_.distortion)
    cv::remap(linear_bgr, light, distort_x_, distort_y_, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  else
    light = linear_bgr;
  cv::GaussianBlur(light, light, cv::Size(5, 5), optics_blur_sigma_, optics_blur_sigma_,
                   cv::BORDER_REFLECT101);
  const cv::Mat raw = read_out(light, exposure, frame);
  if (!params_.bayer) return raw;
  // RGGB from the top-left pixel; OpenCV names the pattern by its second row and column.
  cv::Mat bgr;
  cv::demosaicing(raw, bgr, cv::COLOR_BayerBG2BGR);
  return bgr;
}

cv::Mat RealisticCamera::read_out(const cv::Mat& light, const Exposure& e, int frame) const {
  const int W = light.cols, H = light.rows;
  // Electrons per unit of linear light: the full well at the reference exposure.
  const double electrons = params_.full_well_electrons * e.time / params_.reference_exposure;
  const auto shot = noise_.gaussian(frame, kShotStream), read = noise_.gaussian(frame, kReadStream);
  const double to_level = e.gain / params_.full_well_electrons;
  cv::Mat raw(H, W, params_.bayer ? CV_8U : CV_8UC3);
  auto level = [&](double light_value, float vignette, int c, std::size_t idx) {
    double el = light_value * electrons * vignette;
    if (params_.sensor_noise)
      el += std::sqrt(std::max(el, 0.0)) * shot(idx) + params_.read_noise_electrons * read(idx);
    const double v = std::clamp(el * to_level * e.white_balance[c], 0.0, 1.0);
    return static_cast<std::uint8_t>(std::lround(255.0 * std::pow(v, 1.0 / kGamma)));
  };
  for (int y = 0; y < H; ++y) {
    const auto* l = light.ptr<cv::Vec3f>(y);
    const auto* vg = vignette_.ptr<float>(y);
    auto* o = raw.ptr<std::uint8_t>(y);
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(W);
    for (int x = 0; x < W; ++x) {
      const std::size_t idx = row + static_cast<std::size_t>(x);
      if (params_.bayer) {
        // RGGB: red on even rows and columns, blue on odd ones, green between (BGR channel index).
        const int c = (y % 2 == 0) ? (x % 2 == 0 ? 2 : 1) : (x % 2 == 0 ? 1 : 0);
        o[x] = level(l[x][c], vg[x], c, idx);
      } else {
        for (int c = 0; c < 3; ++c)
          o[3 * x + c] = level(l[x][c], vg[x], c, 3 * idx + static_cast<std::size_t>(c));
      }
    }
  }
  return raw;
}

cv::Mat RealisticCamera::register_depth(const cv::Mat& depth16, int frame, double depth_map_factor) const {
  cv::Mat out;
  if (params_.distortion || params_.depth_registration)
    cv::remap(depth16, out, depth_x_, depth_y_, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
  else
    out = depth16.clone();
  if (params_.depth_millimetres) {
    // OpenNI reports whole millimetres; the PNG scales them (5 levels a millimetre at 5000/m).
    const double step = depth_map_factor / 1000.0;
    out.forEach<std::uint16_t>([step](std::uint16_t& v, const int*) {
      v = cv::saturate_cast<std::uint16_t>(std::lround(std::round(v / step) * step));
    });
  }
  if (params_.speckle_holes) {
    // Holes of up to 3 x 3 pixels where the speckle pattern was not matched.
    const auto hole = noise_.uniform(frame, kHoleStream);
    cv::Mat seeds(out.size(), CV_8U, cv::Scalar(0));
    for (int y = 0; y < out.rows; ++y) {
      auto* s = seeds.ptr<std::uint8_t>(y);
      for (int x = 0; x < out.cols; ++x)
        s[x] = hole(static_cast<std::size_t>(y) * static_cast<std::size_t>(out.cols) +
                    static_cast<std::size_t>(x)) < params_.speckle_hole_rate
                   ? 255
                   : 0;
    }
    cv::dilate(seeds, seeds, cv::Mat::ones(3, 3, CV_8U));
    out.setTo(0, seeds);
  }
  return out;
}

cv::Mat RealisticCamera::warp_labels(const cv::Mat& labels) const {
  if (!params_.distortion) return labels;
  cv::Mat out;
  cv::remap(labels, out, distort_x_, distort_y_, cv::INTER_NEAREST, cv::BORDER_REPLICATE);
  return out;
}

}  // namespace lrd::synth
