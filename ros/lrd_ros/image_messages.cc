#include "lrd_ros/image_messages.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <opencv2/imgproc.hpp>

#include "lrd/util/error.h"

namespace lrd_ros {
namespace {

// The size fields against the data before any pixel is read.
void check_layout(const sensor_msgs::Image& m, int bytes_per_pixel, int bytes_per_channel = 1) {
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
  if (m.data.size() < static_cast<std::size_t>(m.step) * m.height)
    throw lrd::Error(
        fmt::format("{} bytes of data for {} rows of {} bytes", m.data.size(), m.height, m.step));
  if (m.is_bigendian != 0 && bytes_per_channel > 1)
    throw lrd::Error("big-endian " + m.encoding + " images are not supported");
}

// A view of the message's data (valid while the message lives).
cv::Mat view(const sensor_msgs::Image& m, int type) {
  return {static_cast<int>(m.height), static_cast<int>(m.width), type,
          const_cast<unsigned char*>(m.data.data()), static_cast<std::size_t>(m.step)};
}

sensor_msgs::Image header_only(const cv::Mat& image, const ros::Time& stamp, const std::string& frame_id,
                               const std::string& encoding) {
  sensor_msgs::Image m;
  m.header.stamp = stamp;
  m.header.frame_id = frame_id;
  m.height = static_cast<std::uint32_t>(image.rows);
  m.width = static_cast<std::uint32_t>(image.cols);
  m.encoding = encoding;
  m.is_bigendian = 0;
  m.step = static_cast<std::uint32_t>(image.cols * image.elemSize());
  m.data.resize(static_cast<std::size_t>(m.step) * m.height);
  return m;
}

void copy_rows(const cv::Mat& image, sensor_msgs::Image& m) {
  for (int r = 0; r < image.rows; ++r)
    std::memcpy(m.data.data() + static_cast<std::size_t>(r) * m.step, image.ptr(r), m.step);
}

}  // namespace

double to_seconds(const ros::Time& stamp) {
  // A message's raw fields may carry nsec >= 1e9 (ros::Time normalises only what it computes).
  const std::uint64_t sec = stamp.sec + stamp.nsec / 1000000000u;
  const std::string text = fmt::format("{}.{:09d}", sec, stamp.nsec % 1000000000u);
  return std::strtod(text.c_str(), nullptr);
}

ros::Time to_stamp(double seconds) {
  if (!(seconds >= 0.0) || seconds > 4.0e9)
    throw lrd::Error(fmt::format("timestamp {} is not a ROS time", seconds));
  const std::string text = fmt::format("{:.6f}", seconds);
  const std::size_t dot = text.find('.');
  ros::Time t;
  t.sec = static_cast<std::uint32_t>(std::strtoul(text.substr(0, dot).c_str(), nullptr, 10));
  t.nsec = static_cast<std::uint32_t>(std::strtoul(text.substr(dot + 1).c_str(), nullptr, 10) * 1000);
  return t;
}

cv::Mat colour_from_message(const sensor_msgs::Image& m) {
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

cv::Mat depth_from_message(const sensor_msgs::Image& m) {
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

sensor_msgs::Image colour_message(const cv::Mat& bgr, const ros::Time& stamp, const std::string& frame_id) {
  CV_Assert(bgr.type() == CV_8UC3);
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  sensor_msgs::Image m = header_only(rgb, stamp, frame_id, "rgb8");
  copy_rows(rgb, m);
  return m;
}

sensor_msgs::Image depth_message(const cv::Mat& metres, const ros::Time& stamp, const std::string& frame_id) {
  CV_Assert(metres.type() == CV_32FC1);
  sensor_msgs::Image m = header_only(metres, stamp, frame_id, "32FC1");
  copy_rows(metres, m);
  return m;
}

sensor_msgs::Image image_message(const cv::Mat& image, const ros::Time& stamp, const std::string& frame_id) {
  CV_Assert(image.type() == CV_8UC3 || image.type() == CV_8UC1);
  if (image.type() == CV_8UC3) return colour_message(image, stamp, frame_id);
  sensor_msgs::Image m = header_only(image, stamp, frame_id, "mono8");
  copy_rows(image, m);
  return m;
}

lrd::io::SourceCamera camera_from_message(const sensor_msgs::CameraInfo& info) {
  if (info.width == 0 || info.height == 0)
    throw lrd::Error(fmt::format("camera_info has a zero size ({}x{})", info.width, info.height));
  if (!(info.K[0] > 0.0) || !(info.K[4] > 0.0))
    throw lrd::Error("camera_info is uncalibrated (K has no positive focal lengths)");
  lrd::io::SourceCamera c;
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.fx = info.K[0];
  c.fy = info.K[4];
  c.cx = info.K[2];
  c.cy = info.K[5];
  if (!info.D.empty() && info.distortion_model != "plumb_bob" &&
      info.distortion_model != "rational_polynomial")
    throw lrd::Error("camera_info distortion model '" + info.distortion_model +
                     "' is not supported (plumb_bob, rational_polynomial)");
  const auto d = [&info](std::size_t i) { return i < info.D.size() ? info.D[i] : 0.0; };
  c.k1 = d(0);
  c.k2 = d(1);
  c.p1 = d(2);
  c.p2 = d(3);
  c.k3 = d(4);
  return c;
}

sensor_msgs::CameraInfo camera_info_message(const lrd::camera::PinholeCamera& camera, const ros::Time& stamp,
                                            const std::string& frame_id) {
  sensor_msgs::CameraInfo info;
  info.header.stamp = stamp;
  info.header.frame_id = frame_id;
  info.width = static_cast<std::uint32_t>(camera.width);
  info.height = static_cast<std::uint32_t>(camera.height);
  info.distortion_model = "plumb_bob";
  const lrd::camera::Distortion& d = camera.distortion;
  info.D = {d.k1, d.k2, d.p1, d.p2, d.k3};
  info.K = {camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0};
  info.R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.P = {camera.fx, 0.0, camera.cx, 0.0, 0.0, camera.fy, camera.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  return info;
}

}  // namespace lrd_ros
