#include "lrd_ros/image_messages.h"

#include <algorithm>

#include "lrd/bag/camera_info.h"
#include "lrd/bag/image_pixels.h"
#include "lrd/bag/stamp.h"

namespace lrd_ros {
namespace {

// The pixels' fields of a message (the checks and conversions are shared with ROS 2 bags).
lrd::bag::ImageView view_of(const sensor_msgs::Image& m) {
  return {m.width, m.height, m.encoding, m.is_bigendian, m.step, m.data.data(), m.data.size()};
}

sensor_msgs::Image message_of(const lrd::bag::ImagePixels& p, const ros::Time& stamp,
                              const std::string& frame_id) {
  sensor_msgs::Image m;
  m.header.stamp = stamp;
  m.header.frame_id = frame_id;
  m.height = p.height;
  m.width = p.width;
  m.encoding = p.encoding;
  m.is_bigendian = 0;
  m.step = p.step;
  m.data = p.data;
  return m;
}

}  // namespace

double to_seconds(const ros::Time& stamp) {
  return lrd::bag::to_seconds({stamp.sec, stamp.nsec});
}

ros::Time to_stamp(double seconds) {
  const lrd::bag::Stamp s = lrd::bag::to_stamp(seconds);
  ros::Time t;
  t.sec = static_cast<std::uint32_t>(s.sec);
  t.nsec = s.nanosec;
  return t;
}

cv::Mat colour_from_message(const sensor_msgs::Image& m) {
  return lrd::bag::colour_from_image(view_of(m));
}

cv::Mat depth_from_message(const sensor_msgs::Image& m) {
  return lrd::bag::depth_from_image(view_of(m));
}

sensor_msgs::Image colour_message(const cv::Mat& bgr, const ros::Time& stamp, const std::string& frame_id) {
  return message_of(lrd::bag::colour_pixels(bgr), stamp, frame_id);
}

sensor_msgs::Image depth_message(const cv::Mat& metres, const ros::Time& stamp, const std::string& frame_id) {
  return message_of(lrd::bag::depth_pixels(metres), stamp, frame_id);
}

sensor_msgs::Image image_message(const cv::Mat& image, const ros::Time& stamp, const std::string& frame_id) {
  CV_Assert(image.type() == CV_8UC3 || image.type() == CV_8UC1);
  if (image.type() == CV_8UC3) return colour_message(image, stamp, frame_id);
  return message_of(lrd::bag::mono_pixels(image), stamp, frame_id);
}

lrd::io::SourceCamera camera_from_message(const sensor_msgs::CameraInfo& info) {
  lrd::bag::CameraCalibration c;
  c.width = info.width;
  c.height = info.height;
  c.distortion_model = info.distortion_model;
  c.d = info.D;
  std::copy(info.K.begin(), info.K.end(), c.k.begin());
  return lrd::bag::camera_from_calibration(c);
}

sensor_msgs::CameraInfo camera_info_message(const lrd::camera::PinholeCamera& camera, const ros::Time& stamp,
                                            const std::string& frame_id) {
  const lrd::bag::CameraCalibration c = lrd::bag::calibration_of(camera);
  sensor_msgs::CameraInfo info;
  info.header.stamp = stamp;
  info.header.frame_id = frame_id;
  info.width = c.width;
  info.height = c.height;
  info.distortion_model = c.distortion_model;
  info.D = c.d;
  std::copy(c.k.begin(), c.k.end(), info.K.begin());
  std::copy(c.r.begin(), c.r.end(), info.R.begin());
  std::copy(c.p.begin(), c.p.end(), info.P.begin());
  return info;
}

}  // namespace lrd_ros
