#pragma once
// sensor_msgs Image fields (the same in ROS 1 and ROS 2) to and from OpenCV images, checked: every
// field is validated before a byte of data is read, so a malformed message is an lrd::Error
// ("encoding 'yuv422' is not a colour encoding ...") and never a crash. Callers add where the
// message came from (a bag and topic, a subscription).
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace lrd::bag {

// The fields of an image message that describe its pixels; data points into the message.
struct ImageView {
  std::uint32_t width = 0, height = 0;
  std::string encoding;
  std::uint8_t is_bigendian = 0;
  std::uint32_t step = 0;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;  // bytes at data
};

// Colour: rgb8, bgr8, rgba8, bgra8 or mono8 -> CV_8UC3 BGR.
[[nodiscard]] cv::Mat colour_from_image(const ImageView& image);
// Depth: 32FC1 metres (NaN and infinity become 0, "no measurement"; a negative value is an
// error) or 16UC1 millimetres (REP 118) -> CV_32FC1 metres.
[[nodiscard]] cv::Mat depth_from_image(const ImageView& image);

// An image's pixels as a message carries them (rows packed, little-endian).
struct ImagePixels {
  std::uint32_t width = 0, height = 0;
  std::string encoding;
  std::uint32_t step = 0;
  std::vector<std::uint8_t> data;
};

// BGR -> rgb8 (what a TUM bag carries), metres -> 32FC1, single-channel 8-bit -> mono8.
[[nodiscard]] ImagePixels colour_pixels(const cv::Mat& bgr);
[[nodiscard]] ImagePixels depth_pixels(const cv::Mat& metres);
[[nodiscard]] ImagePixels mono_pixels(const cv::Mat& grey);

}  // namespace lrd::bag
