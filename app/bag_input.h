#pragma once
// The CLI's bag options: ROS 2 bags (MCAP, sqlite3) are always read and written (our own code in
// lrd/rosbag2); ROS 1 bags need a build with ROS 1, and without it say so and fail.
#include <filesystem>
#include <memory>
#include <string>

#include "lrd/io/frame_source.h"

namespace lrd::app {

struct BagCli {
  std::string bag;
  std::string rgb_topic = "/camera/rgb/image_color";
  std::string depth_topic = "/camera/depth/image";
  std::string camera_info_topic = "/camera/rgb/camera_info";
  std::string gt_from_tf;  // PARENT:CHILD
};

// `run --bag`: the bag as a frame source, by what the path is: a .mcap or .db3 file or a folder
// with metadata.yaml (ROS 2), anything else a ROS 1 bag. Throws lrd::Error for a bag it cannot
// use, or for a ROS 1 bag when this build has no ROS 1.
[[nodiscard]] std::shared_ptr<const io::FrameSource> open_bag(const BagCli& cli);

// `synth --bag`: the sequence folder just written, as a TUM-style bag with its settings' camera:
// BAG.mcap or BAG.db3 a ROS 2 bag, anything else a ROS 1 bag.
void write_folder_as_bag(const std::filesystem::path& folder, const std::filesystem::path& bag);

}  // namespace lrd::app
