#pragma once
// What a caller hands lrd::System for one frame, checked and brought to the form the stages use:
// a colour image (BGR, RGB or grey, 8 bit), a depth image (16-bit in the camera's depth units or
// float metres) and an optional mask of pixels to ignore, all of the camera's size.
#include <opencv2/core.hpp>

#include "lrd/camera/pinhole_camera.h"

namespace lrd::data {

// Throws lrd::Error naming what is wrong with the images for `camera` (type, size).
void check_rgbd_input(const cv::Mat& rgb, const cv::Mat& depth, const cv::Mat& mask,
                      const camera::PinholeCamera& camera);
// The grey image features are found in (`rgb` itself when it is grey already).
[[nodiscard]] cv::Mat grey_of(const cv::Mat& rgb, const camera::PinholeCamera& camera);
// Depth in metres as CV_32FC1 (`depth` itself when it is so already).
[[nodiscard]] cv::Mat depth_in_metres(const cv::Mat& depth, const camera::PinholeCamera& camera);
// The colour image as BGR in its own buffer (what the dense map keeps of a keyframe).
[[nodiscard]] cv::Mat bgr_copy_of(const cv::Mat& rgb, const camera::PinholeCamera& camera);

}  // namespace lrd::data
