#pragma once
// The CLI's rosbag options, built with or without ROS: without it they say so and fail.
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

// `run --bag`: the bag as a frame source. Throws lrd::Error for a bag it cannot use, or when this
// build has no ROS.
[[nodiscard]] std::shared_ptr<const io::FrameSource> open_bag(const BagCli& cli);

// `synth --bag`: the sequence folder just written, as a TUM-style bag with its settings' camera.
void write_folder_as_bag(const std::filesystem::path& folder, const std::filesystem::path& bag);

}  // namespace lrd::app
