#pragma once
// sensor_msgs images and camera_info to and from what lrd-slam works with (the checks and
// conversions shared with ROS 2 bags, lrd/bag/), checked: every field
// of a message is validated before a byte of its data is read, so a malformed message is an
// lrd::Error ("encoding 'yuv422' is not a colour encoding ...") and never a crash. Callers add
// where the message came from (a bag and topic, a subscription).
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/io/frame_source.h"

namespace lrd_ros {

// A stamp as seconds, exactly as the TUM text files' "%.6f" stamps parse: the decimal digits of
// sec.nsec are read as one number (a sum sec + 1e-9 * nsec can round differently), so a frame
// read from a bag has the same double timestamp as from the folder made of the same bag.
[[nodiscard]] double to_seconds(const ros::Time& stamp);
// Seconds (TUM layout: microseconds) as a stamp, through the same "%.6f" text.
[[nodiscard]] ros::Time to_stamp(double seconds);

// Colour: rgb8, bgr8, rgba8, bgra8 or mono8 -> CV_8UC3 BGR.
[[nodiscard]] cv::Mat colour_from_message(const sensor_msgs::Image& message);
// Depth: 32FC1 metres (NaN and infinity become 0, "no measurement"; a negative value is an
// error) or 16UC1 millimetres (REP 118) -> CV_32FC1 metres.
[[nodiscard]] cv::Mat depth_from_message(const sensor_msgs::Image& message);

// BGR -> rgb8 and metres -> 32FC1 messages (what a TUM bag carries).
[[nodiscard]] sensor_msgs::Image colour_message(const cv::Mat& bgr, const ros::Time& stamp,
                                                const std::string& frame_id);
[[nodiscard]] sensor_msgs::Image depth_message(const cv::Mat& metres, const ros::Time& stamp,
                                               const std::string& frame_id);
// A rgb8 or mono8 image message of an 8-bit image (BGR or single channel).
[[nodiscard]] sensor_msgs::Image image_message(const cv::Mat& image, const ros::Time& stamp,
                                               const std::string& frame_id);

// The intrinsics and distortion of a camera_info (plumb_bob or rational_polynomial: k1 k2 p1 p2
// k3). Throws lrd::Error for a zero size or an uncalibrated (all-zero) K.
[[nodiscard]] lrd::io::SourceCamera camera_from_message(const sensor_msgs::CameraInfo& info);
[[nodiscard]] sensor_msgs::CameraInfo camera_info_message(const lrd::camera::PinholeCamera& camera,
                                                          const ros::Time& stamp,
                                                          const std::string& frame_id);

}  // namespace lrd_ros
