#pragma once
// The ROS nodes' parameters (lrdslam_ros's private ~name, lrdslam_ros2's --ros-args -p name:=...):
// one table of names, defaults and checks for both, read through whatever parameter store the
// node's ROS offers. No ROS here: the table builds with the library, and the ROS 1 node includes
// it as C++17.
#include <filesystem>
#include <string>

#include "lrd/node/node_system.h"

namespace lrd::node {

// Where a node's parameters come from. Each get leaves `value` as it is (the default) when the
// parameter is not set, and throws lrd::Error naming it when it is set to a value of another type.
class ParamReader {
 public:
  virtual ~ParamReader() = default;
  virtual void get(const std::string& name, std::string& value) const = 0;
  virtual void get(const std::string& name, bool& value) const = 0;
  virtual void get(const std::string& name, int& value) const = 0;
  virtual void get(const std::string& name, double& value) const = 0;
  // How the node's users write the parameter's name (ROS 1: "~name"), for errors.
  [[nodiscard]] virtual std::string display(const std::string& name) const { return name; }
};

// What is published and how often.
struct PublishSettings {
  std::string map_frame = "map";
  std::string camera_frame;  // "" : the images' frame_id
  // A z-up frame over the map (whose axes are the first camera's: x right, y down, z forward),
  // published once as a static transform so rviz's orbit view has the floor below; "" : none.
  std::string world_frame = "world";
  double map_period_s = 1.0;        // map_points and keyframes at most this often
  double dense_period_s = 5.0;      // dense_map at most this often (it merges every keyframe's cloud)
  double occupancy_period_s = 5.0;  // occupancy at most this often (it casts every keyframe's rays)
  double path_period_s = 1.0;       // the growing path at most this often (and after loops and saves)
};

struct NodeParams {
  std::string rgb_topic = "/camera/rgb/image_color";
  std::string depth_topic = "/camera/depth/image";
  std::string camera_info_topic = "/camera/rgb/camera_info";
  NodeSettings system;
  PublishSettings publish;
  int queue_size = 2;  // frames waiting for tracking (the oldest dropped beyond)
  std::filesystem::path output_dir = "lrdslam_output";
  double warn_period_s = 5.0;  // throttle of the drop warnings
  // Colour and depth are paired when their stamps are this close (s; TUM's associate.py rule).
  double max_pair_dt = 0.02;
  // > 0: the map to output_dir/map.lrdmap and the trajectory so far to output_dir/CameraTrajectory.txt
  // every so many seconds and after each loop closure (autosave/autosaver.h); 0: at stop only.
  double autosave_s = 0.0;
  // How the node's users write a parameter (ROS 1: "~"), for the messages that name one.
  std::string param_prefix;

  // The parameters in the table; throws lrd::Error for a value out of range.
  static NodeParams from(const ParamReader& reader);
};

}  // namespace lrd::node
