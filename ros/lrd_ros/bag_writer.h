#pragma once
// Writes an RGB-D sequence as a TUM-style rosbag: the topics, message types and frame ids of the
// TUM RGB-D bags, so what reads theirs reads ours (`lrdslam synth --bag`).
#include <filesystem>

#include "lrd/bag/bag_layout.h"
#include "lrd/camera/pinhole_camera.h"
#include "lrd/io/frame_source.h"
#include "lrd_ros/bag_sequence.h"

namespace lrd_ros {

// The topics and frame ids, shared with the ROS 2 bag writer.
using BagLayout = lrd::bag::BagLayout;

// Each frame of `source` as colour (rgb8), depth (32FC1 metres, exactly the floats the source
// decodes), and camera_info on both cameras' topics, stamped with the frame's timestamps; its
// ground truth, if any, as /tf transforms gt_parent -> gt_child. Throws lrd::Error naming `bag`
// when it cannot be written.
void write_bag(const lrd::io::FrameSource& source, const lrd::camera::PinholeCamera& camera,
               const std::filesystem::path& bag, const BagLayout& layout = {});

}  // namespace lrd_ros
