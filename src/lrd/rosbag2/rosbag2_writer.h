#pragma once
// Writes an RGB-D sequence as a ROS 2 bag in the TUM bags' layout (`lrdslam synth --bag`): the
// topics, frame ids, camera_info and /tf ground truth of the ROS 1 bag writer, as ROS 2 messages.
// BAG.mcap: one MCAP file (ros2 profile, ros2msg schemas, cdr channels, chunk indexes and
// statistics). BAG.db3: rosbag2's sqlite3 file with a metadata.yaml beside it, as rosbag2 writes a
// bag folder. Written beside the final names and renamed into place.
#include <filesystem>

#include "lrd/bag/bag_layout.h"
#include "lrd/camera/pinhole_camera.h"
#include "lrd/io/frame_source.h"
#include "lrd/rosbag2/compression.h"

namespace lrd::rosbag2 {

// True for a path this writer writes (.mcap or .db3).
[[nodiscard]] bool is_rosbag2_path(const std::filesystem::path& bag);

// Each frame of `source` as colour (rgb8), depth (32FC1 metres, exactly the floats the source
// decodes), and camera_info on both cameras' topics, stamped with the frame's timestamps; its
// ground truth, if any, as /tf transforms gt_parent -> gt_child. `compression` is the MCAP
// chunks'. Throws lrd::Error naming the file when it cannot be written.
void write_rosbag2(const io::FrameSource& source, const camera::PinholeCamera& camera,
                   const std::filesystem::path& bag, const bag::BagLayout& layout = {},
                   Compression compression = Compression::zstd);

}  // namespace lrd::rosbag2
