#pragma once
// Whole images resampled to the ideal pinhole camera: the dense stage back-projects and projects
// every pixel with fx, fy, cx, cy alone, so a keyframe's colour, depth and mask are undistorted
// once before it (the `tum` realism profile renders the lens distortion; read raw, pixels at the
// image border land centimetres off). Without distortion nothing is resampled.
#include <opencv2/core.hpp>

#include "lrd/camera/pinhole_camera.h"

namespace lrd::camera {

class ImageUndistorter {
 public:
  explicit ImageUndistorter(const PinholeCamera& camera);

  // Whether the camera has a distortion to remove (otherwise every call returns its input).
  [[nodiscard]] bool active() const { return !map_x_.empty(); }
  // Colour (or any smooth image): bilinear. Pixels from outside the raw image are 0.
  [[nodiscard]] cv::Mat smooth(const cv::Mat& raw) const;
  // Depth, masks, labels: the nearest raw pixel (no value mixes two surfaces or two labels).
  [[nodiscard]] cv::Mat nearest(const cv::Mat& raw) const;

 private:
  [[nodiscard]] cv::Mat remap(const cv::Mat& raw, int interpolation) const;

  cv::Mat map_x_, map_y_;  // CV_32FC1: the raw pixel of each ideal one
};

}  // namespace lrd::camera
