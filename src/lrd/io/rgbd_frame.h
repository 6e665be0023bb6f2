#pragma once
// One RGB-D frame of a sequence: where its images are (FrameEntry) and the decoded images
// (RgbdFrame).
#include <cstddef>
#include <filesystem>
#include <opencv2/core.hpp>

namespace lrd::io {

struct FrameEntry {
  double timestamp = 0.0;  // of the rgb image; the frame's time
  std::filesystem::path rgb_path;
  double depth_timestamp = 0.0;
  std::filesystem::path depth_path;
};

struct RgbdFrame {
  std::size_t index = 0;  // position in the sequence
  double timestamp = 0.0;
  cv::Mat rgb;    // CV_8UC3, BGR (OpenCV order)
  cv::Mat depth;  // CV_32FC1, metres; 0 = no measurement
};

// Decodes both images of `entry`: the colour image as 8-bit BGR, the depth image (a 16-bit
// single-channel PNG) as value / depth_factor metres, keeping 0 as invalid. Throws lrd::Error
// naming the image file for a missing or undecodable image, a depth image that is not 16-bit
// single channel ("expected 16-bit depth PNG, got 8-bit") and rgb/depth size mismatch.
[[nodiscard]] RgbdFrame load_rgbd_frame(const FrameEntry& entry, std::size_t index, double depth_factor);

// A 16-bit depth image (CV_16UC1, value per metre depth_factor > 0) as CV_32FC1 metres, 0 kept as
// no measurement; every source converts alike, so a rendered frame equals its PNG read back.
[[nodiscard]] cv::Mat depth_in_metres(const cv::Mat& raw, double depth_factor);

}  // namespace lrd::io
