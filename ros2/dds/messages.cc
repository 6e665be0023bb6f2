#include "messages.h"

#include "lrd/bag/camera_info.h"
#include "lrd/bag/stamp.h"

namespace lrd_ros2 {

namespace {

lrd::bag::ImageView view_of(const sensor_msgs_msg_dds__Image_& m) {
  return {m.width,        m.height,      m.encoding == nullptr ? "" : m.encoding, m.is_bigendian, m.step,
          m.data._buffer, m.data._length};
}

}  // namespace

double to_seconds(const builtin_interfaces_msg_dds__Time_& stamp) {
  return lrd::bag::to_seconds({stamp.sec, stamp.nanosec});
}

builtin_interfaces_msg_dds__Time_ to_time(double seconds) {
  const lrd::bag::Stamp s = lrd::bag::to_stamp(seconds);
  return {static_cast<std::int32_t>(s.sec), s.nanosec};
}

std_msgs_msg_dds__Header_ header(double seconds, const std::string& frame) {
  return {to_time(seconds), text(frame)};
}

cv::Mat colour_from_message(const sensor_msgs_msg_dds__Image_& m) {
  return lrd::bag::colour_from_image(view_of(m));
}

cv::Mat depth_from_message(const sensor_msgs_msg_dds__Image_& m) {
  return lrd::bag::depth_from_image(view_of(m));
}

lrd::io::SourceCamera camera_from_message(const sensor_msgs_msg_dds__CameraInfo_& m) {
  lrd::bag::CameraCalibration c;
  c.width = m.width;
  c.height = m.height;
  c.distortion_model = m.distortion_model == nullptr ? "" : m.distortion_model;
  c.d.assign(m.d._buffer, m.d._buffer + m.d._length);
  std::copy(std::begin(m.k), std::end(m.k), c.k.begin());
  std::copy(std::begin(m.r), std::end(m.r), c.r.begin());
  std::copy(std::begin(m.p), std::end(m.p), c.p.begin());
  return lrd::bag::camera_from_calibration(c);
}

sensor_msgs_msg_dds__Image_ image_message(const lrd::bag::ImagePixels& p, double seconds,
                                          const std::string& frame) {
  sensor_msgs_msg_dds__Image_ m{};
  m.header = header(seconds, frame);
  m.height = p.height;
  m.width = p.width;
  m.encoding = text(p.encoding);
  m.is_bigendian = 0;
  m.step = p.step;
  m.data._length = m.data._maximum = static_cast<std::uint32_t>(p.data.size());
  m.data._buffer = const_cast<std::uint8_t*>(p.data.data());
  m.data._release = false;
  return m;
}

geometry_msgs_msg_dds__Pose_ pose_message(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  const Eigen::Vector3d t = T.translation();
  return {{t.x(), t.y(), t.z()}, {q.x(), q.y(), q.z(), q.w()}};
}

geometry_msgs_msg_dds__Transform_ transform_message(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  const Eigen::Vector3d t = T.translation();
  return {{t.x(), t.y(), t.z()}, {q.x(), q.y(), q.z(), q.w()}};
}

Eigen::Isometry3d from_transform(const geometry_msgs_msg_dds__Transform_& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  return T;
}

}  // namespace lrd_ros2
