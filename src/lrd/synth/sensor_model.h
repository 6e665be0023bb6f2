#pragma once
// A Kinect-like RGB-D sensor applied to ideal renders.
// Depth (after Khoshelham & Elberink 2012): structured-light disparity d = f·b / z with Gaussian
// noise and 1/8-pixel quantisation, so the depth error grows with z²; invalid beyond the working
// range; projector shadows on the far side of depth edges (the ordering test of structured light);
// dropouts at grazing incidence and random flying pixels at edges. RGB: optics blur and noise.
// All noise is a function of (seed, frame, pixel), so the actor-free "static" render gets exactly
// the same noise as the real one wherever the actors are not.
#include <cstdint>
#include <opencv2/core.hpp>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/synth/noise_table.h"
#include "lrd/synth/rasterizer.h"

namespace lrd::synth {

struct SensorParams {
  double baseline = 0.075;           // m, IR projector to IR camera
  double disparity_sigma = 0.07;     // px
  double disparity_step = 0.125;     // px (1/8 sub-pixel)
  double min_depth = 0.45;           // m
  double max_depth = 4.5;            // m
  double grazing_cos_invalid = 0.1;  // |cos| below: always a hole
  double grazing_cos_random = 0.25;  // below: a hole with growing probability
  double edge_dropout = 0.5;         // probability of a hole next to a depth edge
  double rgb_noise_sigma = 2.0;      // grey levels
  double rgb_blur_sigma = 0.6;       // px, optics
};

class SensorModel {
 public:
  SensorModel(const camera::PinholeCamera& camera, SensorParams params, std::uint64_t seed);
  // 16-bit depth image (value = metres × depth_map_factor, 0 = invalid).
  [[nodiscard]] cv::Mat depth_image(const RenderBuffers& ideal, int frame) const;
  // Blurred, noisy 8-bit BGR image from an ideal (or motion-blurred) render.
  [[nodiscard]] cv::Mat rgb_image(const cv::Mat& ideal_bgr, int frame) const;
  [[nodiscard]] const SensorParams& params() const { return params_; }
  [[nodiscard]] const NoiseTable& noise() const { return noise_; }

 private:
  camera::PinholeCamera cam_;
  SensorParams params_;
  NoiseTable noise_;
};

}  // namespace lrd::synth
