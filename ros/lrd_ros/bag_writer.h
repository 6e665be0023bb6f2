#pragma once
// Writes an RGB-D sequence as a TUM-style rosbag: the topics, message types and frame ids of the
// TUM RGB-D bags, so what reads theirs reads ours (`lrdslam synth --bag`).
#include <filesystem>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/io/frame_source.h"
#include "lrd_ros/bag_sequence.h"

namespace lrd_ros {

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

// Each frame of `source` as colour (rgb8), depth (32FC1 metres, exactly the floats the source
// decodes), and camera_info on both cameras' topics, stamped with the frame's timestamps; its
// ground truth, if any, as /tf transforms gt_parent -> gt_child. Throws lrd::Error naming `bag`
// when it cannot be written.
void write_bag(const lrd::io::FrameSource& source, const lrd::camera::PinholeCamera& camera,
               const std::filesystem::path& bag, const BagLayout& layout = {});

}  // namespace lrd_ros
