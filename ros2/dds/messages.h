#pragma once
// The idlc-generated ROS 2 messages to and from what lrd-slam works with. Received messages are
// checked by the same code as ROS 1's and ROS 2 bags' (lrd/bag), so a malformed image is an
// lrd::Error naming the problem. Messages made here point into the caller's buffers and strings
// (no copies): they live until the write that sends them returns.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>

#include "geometry_msgs.h"
#include "lrd/bag/image_pixels.h"
#include "lrd/io/frame_source.h"
#include "sensor_msgs.h"

namespace lrd_ros2 {

[[nodiscard]] double to_seconds(const builtin_interfaces_msg_dds__Time_& stamp);
[[nodiscard]] builtin_interfaces_msg_dds__Time_ to_time(double seconds);
// A header whose frame_id points into `frame` (which must outlive the message).
[[nodiscard]] std_msgs_msg_dds__Header_ header(double seconds, const std::string& frame);

[[nodiscard]] cv::Mat colour_from_message(const sensor_msgs_msg_dds__Image_& m);
[[nodiscard]] cv::Mat depth_from_message(const sensor_msgs_msg_dds__Image_& m);
[[nodiscard]] lrd::io::SourceCamera camera_from_message(const sensor_msgs_msg_dds__CameraInfo_& m);

// An image message over `pixels`' bytes.
[[nodiscard]] sensor_msgs_msg_dds__Image_ image_message(const lrd::bag::ImagePixels& pixels, double seconds,
                                                        const std::string& frame);

[[nodiscard]] geometry_msgs_msg_dds__Pose_ pose_message(const Eigen::Isometry3d& T);
[[nodiscard]] geometry_msgs_msg_dds__Transform_ transform_message(const Eigen::Isometry3d& T);
[[nodiscard]] Eigen::Isometry3d from_transform(const geometry_msgs_msg_dds__Transform_& t);

// A view of a std::string as the generated types' char* (they are never written through).
[[nodiscard]] inline char* text(const std::string& s) {
  return const_cast<char*>(s.c_str());
}

}  // namespace lrd_ros2
