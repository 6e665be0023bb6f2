#include "lrd/camera/image_undistorter.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "lrd/util/error.h"

namespace lrd::camera {

ImageUndistorter::ImageUndistorter(const PinholeCamera& camera) {
  if (camera.distortion.is_zero()) return;
  // The same K on both sides: an ideal pixel keeps the calibration's intrinsics.
  cv::initUndistortRectifyMap(camera.K_cv(), camera.distortion_cv(), cv::Mat(), camera.K_cv(),
                              cv::Size(camera.width, camera.height), CV_32FC1, map_x_, map_y_);
}

cv::Mat ImageUndistorter::smooth(const cv::Mat& raw) const {
  return remap(raw, cv::INTER_LINEAR);
}

cv::Mat ImageUndistorter::nearest(const cv::Mat& raw) const {
  return remap(raw, cv::INTER_NEAREST);
}

cv::Mat ImageUndistorter::remap(const cv::Mat& raw, int interpolation) const {
  if (!active() || raw.empty()) return raw;
  if (raw.size() != map_x_.size())
    throw Error("image undistortion: the image is " + std::to_string(raw.cols) + "x" +
                std::to_string(raw.rows) + ", the camera " + std::to_string(map_x_.cols) + "x" +
                std::to_string(map_x_.rows));
  cv::Mat out;
  cv::remap(raw, out, map_x_, map_y_, interpolation, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return out;
}

}  // namespace lrd::camera
