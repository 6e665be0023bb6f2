#pragma once
// What a TUM-style RGB-D bag holds, whatever its format (ROS 1 .bag, ROS 2 sqlite3 or MCAP): the
// topics read or written, the frame ids, and the ground-truth frames on /tf.
#include <string>
#include <utility>

namespace lrd::bag {

struct BagTopics {
  std::string rgb = "/camera/rgb/image_color";          // sensor_msgs Image, colour
  std::string depth = "/camera/depth/image";            // sensor_msgs Image, 32FC1 m or 16UC1 mm
  std::string camera_info = "/camera/rgb/camera_info";  // optional: the camera when none is given
  // --gt-from-tf PARENT:CHILD: the ground truth is CHILD's pose in PARENT from /tf (and
  // /tf_static), e.g. "/world" and "/kinect" in the TUM bags. Empty: none.
  std::string gt_parent, gt_child;
  double max_dt = 0.02;  // colour-depth association, s
};

// What `lrdslam synth --bag` writes: the TUM bags' topics and frame ids.
struct BagLayout {
  BagTopics topics;  // rgb, depth, camera_info; gt_parent/gt_child name the /tf ground truth
  std::string depth_camera_info = "/camera/depth/camera_info";
  std::string rgb_frame = "/openni_rgb_optical_frame";
  std::string depth_frame = "/openni_depth_optical_frame";
  BagLayout() {
    topics.gt_parent = "/world";
    topics.gt_child = "/kinect";
  }
};

// "PARENT:CHILD" -> (parent, child); throws lrd::Error naming the option for anything else.
[[nodiscard]] std::pair<std::string, std::string> parse_tf_pair(const std::string& text);

}  // namespace lrd::bag
