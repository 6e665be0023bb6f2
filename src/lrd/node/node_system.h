#pragma once
// The node's System, configured like `lrdslam run` configures its own (runner::resolve_config and
// configure_system): the node's parameters play the CLI's options, and a camera_info plays the
// bag's. No ROS here: this part builds as C++20 with the library, the node around it as C++17.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/io/frame_source.h"
#include "lrd/system.h"

namespace lrd::node {

struct NodeSettings {
  std::string settings;                     // ~settings: ORB-SLAM2/3 settings file (the camera)
  std::string config;                       // ~config: lrd-slam YAML config
  std::string mode;                         // ~mode: static | semantic | geometric | full ("": the config's)
  std::string segmenter;                    // ~segmenter: a runner::segmenter_preset name ("": the default)
  std::string segmenter_model;              // ~segmenter_model
  bool dense = false;                       // ~dense
  bool yardstick = false;                   // ~yardstick: time Y beside each frame (benchmarks)
  std::string load_map;                     // ~load_map: start from this map file (.lrdmap)
  std::size_t max_queued_frame_events = 4;  // a live node publishes the newest frames
};

// Whether the settings name a camera themselves (~settings, or a config with a camera section);
// otherwise the node waits for a camera_info. Throws lrd::Error for an unreadable file.
[[nodiscard]] bool names_camera(const NodeSettings& settings);

struct NodeSystem {
  std::unique_ptr<lrd::System> system;
  lrd::camera::PinholeCamera camera;
  std::string camera_source;  // "settings FILE", "camera_info", ...
  std::string description;    // mode and segmentation, for the start-up log line
};

// Starts a System (threads running). camera_info: the first one received, when the settings
// name no camera. Throws lrd::Error for bad settings (the node logs it and exits).
[[nodiscard]] NodeSystem make_system(const NodeSettings& settings,
                                     const std::optional<lrd::io::SourceCamera>& camera_info);

// One tracked frame's result, for track_times.txt in `lrdslam run`'s format (so
// bench/ros_node_speed.py compares the node with the CLI on the same frames).
struct FrameTime {
  std::size_t index = 0;  // frames given to the system, from 0
  double timestamp = 0.0;
  lrd::TrackResult result;  // without its mask
};
void write_track_times(const std::filesystem::path& file, const std::vector<FrameTime>& frames);

}  // namespace lrd::node
