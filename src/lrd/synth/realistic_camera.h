#pragma once
// The colour camera and depth registration of the `tum` realism profile
// (docs/synthetic-benchmark.md): what a Kinect v1 does to the light between the scene and the PNG
// files. Colour: auto exposure and white balance chosen from the view, the exposure and
// rolling-shutter readout integrated over sub-frame renders, lens distortion and vignetting, a
// Bayer sensor with shot and read noise, gamma, 8 bits. Depth: warped into the distorted colour
// image with a registration error, speckle holes, whole millimetres. Noise is a function of (seed,
// frame, pixel), as in SensorModel: the actor-free view of a frame gets the same noise wherever the
// actors are not.
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/synth/noise_table.h"
#include "lrd/synth/realism.h"

namespace lrd::synth {

class RealisticCamera {
 public:
  // `optics_blur_sigma` and `noise`: the lens blur and noise tables of the sequence's SensorModel
  // (the noise must outlive this camera).
  RealisticCamera(const camera::PinholeCamera& truth, RealismParams params, double optics_blur_sigma,
                  const NoiseTable& noise);

  struct Exposure {
    double time = 0.0;  // s
    double gain = 1.0;
    cv::Vec3d white_balance{1.0, 1.0, 1.0};  // B, G, R
  };
  // The exposure control's choice for a view, from its render at the frame's instant (8-bit BGR).
  [[nodiscard]] Exposure expose(const cv::Mat& bgr) const;

  // The instants to render for a frame whose middle row is exposed around t (an odd number, t
  // in the middle), and each row's weights over them (rows x instants, CV_32F, rows sum to 1).
  struct ShutterPlan {
    std::vector<double> times;
    cv::Mat row_weights;
  };
  [[nodiscard]] ShutterPlan shutter(double t, const Exposure& exposure) const;
  // The rows of 8-bit BGR sub-frame renders integrated in linear light (CV_32FC3, 0..1).
  [[nodiscard]] cv::Mat integrate(const std::vector<cv::Mat>& renders, const ShutterPlan& plan) const;
  // One render (8-bit BGR) in linear light, for a frame without sub-frames.
  [[nodiscard]] cv::Mat linear(const cv::Mat& bgr) const;
  // Lens, sensor and image processing: linear light at the reference exposure -> 8-bit BGR.
  [[nodiscard]] cv::Mat develop(const cv::Mat& linear_bgr, const Exposure& exposure, int frame) const;

  // A 16-bit depth image of the pinhole render, as the driver registers it to the colour image.
  [[nodiscard]] cv::Mat register_depth(const cv::Mat& depth16, int frame, double depth_map_factor) const;
  // Ground-truth channels (labels, classes) in the colour image's distorted geometry.
  [[nodiscard]] cv::Mat warp_labels(const cv::Mat& labels) const;

  [[nodiscard]] const RealismParams& params() const { return params_; }

 private:
  // The sensor's 8-bit read-out of the light on it: a Bayer mosaic (CV_8U) or three channels.
  [[nodiscard]] cv::Mat read_out(const cv::Mat& light, const Exposure& e, int frame) const;

  camera::PinholeCamera truth_;
  RealismParams params_;
  double optics_blur_sigma_;
  cv::Mat distort_x_, distort_y_;  // colour pixel -> pinhole render pixel (CV_32F)
  cv::Mat depth_x_, depth_y_;      // the same with the registration error
  cv::Mat vignette_;               // CV_32F gain per pixel
  std::vector<float> to_linear_;   // 8-bit level -> linear light
  const NoiseTable& noise_;
};

}  // namespace lrd::synth
