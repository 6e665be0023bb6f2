#pragma once
// `lrdslam ros2-play`: a sequence (folder or bag) published over DDS as a TUM bag carries it and a
// ROS 2 camera driver publishes it: colour (rgb8) and depth (32FC1 m) images with their
// camera_info, and the ground truth on /tf (TUM's /world -> /kinect), at the camera's pace times
// the rate, to drive a ROS 2 node (ours, or any other) in a test or a demo.
#include <filesystem>
#include <memory>
#include <optional>

#include "lrd/bag/bag_layout.h"
#include "lrd/camera/pinhole_camera.h"
#include "lrd/io/frame_source.h"

namespace lrd_ros2 {

struct PlayOptions {
  lrd::bag::BagLayout layout;  // topics and frame ids
  double rate = 1.0;           // times the camera's pace
  double depth_factor = 5000.0;
  double wait_s = 20.0;        // for a subscriber on the colour topic before the first frame
  std::size_t max_frames = 0;  // 0: all
  bool reliable = false;       // the images' QoS: sensor data (best effort) unless asked
};

struct PlayResult {
  std::size_t frames = 0;
  bool subscriber_seen = false;
};

// Publishes every frame of `source` (camera from `camera`) and returns once the last is sent.
// Throws lrd::Error for a frame that cannot be read.
PlayResult play(const lrd::io::FrameSource& source, const lrd::camera::PinholeCamera& camera,
                const PlayOptions& options);

}  // namespace lrd_ros2
