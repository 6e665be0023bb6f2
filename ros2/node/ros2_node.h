#pragma once
// lrdslam_ros2: lrd-slam as a ROS 2 node on Cyclone DDS, a thin adapter over lrd::System as the
// ROS 1 node is: DDS readers with the sensor-data QoS a camera driver uses (best effort, volatile:
// both best-effort and reliable publishers match) feed colour and depth through a FramePairer into
// lrd::node::SlamDriver (frame queue, tracking thread, drops, outputs); Ros2Publisher publishes;
// Graph announces the node and its endpoints in the ROS graph.
#include <memory>
#include <set>
#include <string>
#include <utility>

#include "endpoints.h"
#include "graph.h"
#include "lrd/node/frame_pairer.h"
#include "lrd/node/node_params.h"
#include "lrd/node/slam_driver.h"
#include "participant.h"
#include "ros2_publisher.h"
#include "ros_args.h"
#include "sensor_msgs.h"

namespace lrd_ros2 {

// The node's log lines, as ROS 2's console writes them: "[LEVEL] [seconds] [lrdslam]: message".
void log_line(const char* level, const std::string& node, const std::string& message);

struct NodeIdentity {
  std::string name = "lrdslam";
  std::string ns = "/";
  [[nodiscard]] std::string fqn() const { return (ns == "/" ? "" : ns) + "/" + name; }
};

class Ros2Node {
 public:
  // on_fatal: the tracking thread cannot go on (the node then stops, exit 1).
  Ros2Node(const RosArgs& args, std::function<void()> on_fatal);
  ~Ros2Node();
  Ros2Node(const Ros2Node&) = delete;
  Ros2Node& operator=(const Ros2Node&) = delete;

  void stop() { driver_->stop(); }
  [[nodiscard]] bool failed() const { return driver_->failed(); }

 private:
  struct Incoming {
    cv::Mat image;
    std::string frame_id;
  };
  void on_colour(const sensor_msgs_msg_dds__Image_& m);
  void on_depth(const sensor_msgs_msg_dds__Image_& m);
  void on_camera_info(const sensor_msgs_msg_dds__CameraInfo_& m);
  void on_pair(lrd::node::FramePairer<Incoming>::Pair pair);
  void on_publication(const dds_builtintopic_endpoint_t& endpoint);
  void info(const std::string& m) const { log_line("INFO", id_.name, m); }
  void warn(const std::string& m) const { log_line("WARN", id_.name, m); }

  NodeIdentity id_;
  Distro distro_ = Distro::Humble;
  lrd::node::NodeParams params_;
  std::unique_ptr<Participant> participant_;
  std::unique_ptr<Graph> graph_;
  std::shared_ptr<Ros2Publisher> publisher_;
  std::unique_ptr<lrd::node::SlamDriver> driver_;
  std::unique_ptr<lrd::node::FramePairer<Incoming>> pairer_;
  std::mutex warned_mutex_;
  std::set<std::pair<std::string, std::string>> warned_types_;  // (topic, type) said once
  std::chrono::steady_clock::time_point last_camera_warning_{};
  // Last: their callbacks use everything above; deleting a reader waits for its callback.
  std::unique_ptr<Reader<sensor_msgs_msg_dds__Image_>> colour_, depth_;
  std::unique_ptr<Reader<sensor_msgs_msg_dds__CameraInfo_>> camera_info_;
  dds_entity_t publications_ = 0;  // DCPSPublication: publishers of another type on our inputs
};

}  // namespace lrd_ros2
