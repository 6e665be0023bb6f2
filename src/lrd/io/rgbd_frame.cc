#include "lrd/io/rgbd_frame.h"

#include <cstdint>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "lrd/io/image_file.h"
#include "lrd/util/error.h"

namespace lrd::io {
namespace {

std::string size_str(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows);
}

std::string depth_name(int depth) {
  switch (depth) {
    case CV_8U:
      return "8-bit";
    case CV_8S:
      return "signed 8-bit";
    case CV_16U:
      return "16-bit";
    case CV_16S:
      return "signed 16-bit";
    case CV_32S:
      return "32-bit integer";
    case CV_32F:
      return "32-bit float";
    case CV_64F:
      return "64-bit float";
    default:
      return "unknown-depth";
  }
}

std::string type_str(const cv::Mat& m) {
  const std::string d = depth_name(m.depth());
  return m.channels() == 1 ? d : d + " " + std::to_string(m.channels()) + "-channel";
}

}  // namespace

RgbdFrame load_rgbd_frame(const FrameEntry& entry, std::size_t index, double depth_factor) {
  if (!(depth_factor > 0.0)) {
    throw file_error(entry.depth_path, "depth factor must be > 0, got " + std::to_string(depth_factor));
  }
  RgbdFrame frame;
  frame.index = index;
  frame.timestamp = entry.timestamp;
  frame.rgb = read_image_file(entry.rgb_path, cv::IMREAD_COLOR);

  const cv::Mat raw = read_image_file(entry.depth_path, cv::IMREAD_UNCHANGED);
  if (raw.type() != CV_16UC1) {
    throw file_error(entry.depth_path, "expected 16-bit depth PNG, got " + type_str(raw));
  }
  if (raw.size() != frame.rgb.size()) {
    throw file_error(entry.depth_path, "depth image size " + size_str(raw) +
                                           " does not match rgb image size " + size_str(frame.rgb) + " (" +
                                           entry.rgb_path.string() + ")");
  }
  frame.depth = depth_in_metres(raw, depth_factor);
  return frame;
}

cv::Mat depth_in_metres(const cv::Mat& raw, double depth_factor) {
  // Divide in double so that e.g. 5000 / 5000 is exactly 1 m (convertTo scales in float).
  cv::Mat depth(raw.size(), CV_32FC1);
  for (int r = 0; r < raw.rows; ++r) {
    const auto* src = raw.ptr<std::uint16_t>(r);
    auto* dst = depth.ptr<float>(r);
    for (int c = 0; c < raw.cols; ++c) dst[c] = static_cast<float>(src[c] / depth_factor);
  }
  return depth;
}

}  // namespace lrd::io
