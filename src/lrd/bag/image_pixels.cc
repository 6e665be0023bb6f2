#include "lrd/bag/image_pixels.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>

#include "lrd/util/error.h"

namespace lrd::bag {
namespace {

// The size fields against the data before any pixel is read.
void check_layout(const ImageView& m, int bytes_per_pixel, int bytes_per_channel = 1) {
  if (m.width == 0 || m.height == 0)
    throw lrd::Error(fmt::format("zero-size image ({}x{})", m.width, m.height));
  if (m.width > 1u << 15 || m.height > 1u << 15)
    throw lrd::Error(fmt::format("implausible image size {}x{}", m.width, m.height));
  const std::size_t row = static_cast<std::size_t>(m.width) * static_cast<std::size_t>(bytes_per_pixel);
  if (m.step < row)
    throw lrd::Error(fmt::format("step {} is shorter than a row of {} {} pixels ({} bytes)", m.step, m.width,
                                 m.encoding, row));
  if (m.step % static_cast<std::uint32_t>(bytes_per_channel) != 0)
    throw lrd::Error(
        fmt::format("step {} is not a whole number of {}-byte values", m.step, bytes_per_channel));
  if (m.size < static_cast<std::size_t>(m.step) * m.height)
    throw lrd::Error(fmt::format("{} bytes of data for {} rows of {} bytes", m.size, m.height, m.step));
  if (m.is_bigendian != 0 && bytes_per_channel > 1)
    throw lrd::Error("big-endian " + m.encoding + " images are not supported");
}

// A view of the message's data (valid while the message lives).
cv::Mat view(const ImageView& m, int type) {
  return {static_cast<int>(m.height), static_cast<int>(m.width), type, const_cast<std::uint8_t*>(m.data),
          static_cast<std::size_t>(m.step)};
}

ImagePixels packed(const cv::Mat& image, const std::string& encoding) {
  ImagePixels p;
  p.height = static_cast<std::uint32_t>(image.rows);
  p.width = static_cast<std::uint32_t>(image.cols);
  p.encoding = encoding;
  p.step = static_cast<std::uint32_t>(image.cols * image.elemSize());
  p.data.resize(static_cast<std::size_t>(p.step) * p.height);
  for (int r = 0; r < image.rows; ++r)
    std::memcpy(p.data.data() + static_cast<std::size_t>(r) * p.step, image.ptr(r), p.step);
  return p;
}

}  // namespace

cv::Mat colour_from_image(const ImageView& m) {
  struct Colour {
    const char* encoding;
    int type, code;  // code < 0: copy
  };
  static constexpr Colour kColours[] = {{"rgb8", CV_8UC3, cv::COLOR_RGB2BGR},
                                        {"bgr8", CV_8UC3, -1},
                                        {"rgba8", CV_8UC4, cv::COLOR_RGBA2BGR},
                                        {"bgra8", CV_8UC4, cv::COLOR_BGRA2BGR},
                                        {"mono8", CV_8UC1, cv::COLOR_GRAY2BGR}};
  for (const Colour& c : kColours) {
    if (m.encoding != c.encoding) continue;
    check_layout(m, CV_ELEM_SIZE(c.type));
    cv::Mat bgr;
    if (c.code < 0)
      view(m, c.type).copyTo(bgr);
    else
      cv::cvtColor(view(m, c.type), bgr, c.code);
    return bgr;
  }
  throw lrd::Error("encoding '" + m.encoding +
                   "' is not a colour encoding (rgb8, bgr8, rgba8, bgra8, mono8)");
}

cv::Mat depth_from_image(const ImageView& m) {
  cv::Mat metres;
  if (m.encoding == "32FC1") {
    check_layout(m, 4, 4);
    view(m, CV_32FC1).copyTo(metres);
    // NaN and infinity are REP 118's "no return" (every TUM bag has them); a negative distance is
    // a broken message.
    std::size_t negative = 0;
    float lowest = 0.0f;
    for (int r = 0; r < metres.rows; ++r)
      for (float* z = metres.ptr<float>(r); z != metres.ptr<float>(r) + metres.cols; ++z) {
        if (!std::isfinite(*z)) {
          *z = 0.0f;
        } else if (*z < 0.0f) {
          ++negative;
          lowest = std::min(lowest, *z);
        }
      }
    if (negative > 0)
      throw lrd::Error(fmt::format("{} pixels of negative depth (down to {} m)", negative, lowest));
  } else if (m.encoding == "16UC1" || m.encoding == "mono16") {
    check_layout(m, 2, 2);
    view(m, CV_16UC1).convertTo(metres, CV_32F, 1e-3);
  } else {
    throw lrd::Error("encoding '" + m.encoding +
                     "' is not a depth encoding (32FC1 metres, 16UC1 millimetres)");
  }
  return metres;
}

ImagePixels colour_pixels(const cv::Mat& bgr) {
  CV_Assert(bgr.type() == CV_8UC3);
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return packed(rgb, "rgb8");
}

ImagePixels depth_pixels(const cv::Mat& metres) {
  CV_Assert(metres.type() == CV_32FC1);
  return packed(metres, "32FC1");
}

ImagePixels mono_pixels(const cv::Mat& grey) {
  CV_Assert(grey.type() == CV_8UC1);
  return packed(grey, "mono8");
}

}  // namespace lrd::bag
