#pragma once
// The ROS 2 node's topics under its name (/lrdslam/pose, ...): lrd::node::TopicPublisher (what is
// published and when) with DDS writers as its messages. QoS: what ROS 1 latched (path, map_points,
// keyframes, dense_map, occupancy, state) is reliable + transient_local so a late subscriber
// (rviz2) gets the last one; pose is reliable + transient_local too (keep last 10), as
// subscribers that ask for transient_local (Foxglove's) match only such writers and a volatile
// one matches a writer either way; /tf as tf2_ros broadcasts it (reliable, volatile, keep last
// 100), /tf_static as its static broadcaster does (reliable, transient_local, keep last 1).
#include <memory>
#include <string>

#include "endpoints.h"
#include "geometry_msgs.h"
#include "graph.h"
#include "lrd/node/map_messages.h"
#include "lrd/node/topic_publisher.h"
#include "nav_msgs.h"
#include "participant.h"
#include "sensor_msgs.h"
#include "std_msgs.h"
#include "tf2_msgs.h"
#include "visualization_msgs.h"

namespace lrd_ros2 {

class Ros2Publisher final : public lrd::node::TopicPublisher {
 public:
  // node_prefix: the node's fully qualified name ("/lrdslam"), the topics' namespace.
  Ros2Publisher(Participant& participant, Graph& graph, const std::string& node_prefix,
                lrd::node::PublishSettings settings);
  ~Ros2Publisher() override;

 private:
  void send_state(const std::string& state) override;
  void send_pose(double stamp, const Eigen::Isometry3d& T_map_camera) override;
  void send_path(double stamp, const lrd::io::Trajectory& path) override;
  void send_map(const lrd::events::MapSnapshot& map) override;
  void send_dense_map(const lrd::dense::PointCloud& cloud) override;
  void send_occupancy(const lrd::occupancy::Occupancy& occupancy) override;
  void send_static_transform(const std::string& parent, const std::string& child,
                             const Eigen::Isometry3d& T_parent_child) override;
  [[nodiscard]] bool mask_wanted() const override { return mask_.matched() > 0; }
  [[nodiscard]] bool overlay_wanted() const override { return overlay_.matched() > 0; }
  void send_mask(double stamp, const cv::Mat& mask) override;
  void send_overlay(double stamp, const cv::Mat& bgr) override;
  void warn(const std::string& what) override;

  void send_keyframes(const lrd::events::MapSnapshot& map, double now);
  void send_cloud(Writer<sensor_msgs_msg_dds__PointCloud2_>& writer, const lrd::node::PackedCloud& cloud);

  Writer<geometry_msgs_msg_dds__PoseStamped_> pose_;
  Writer<tf2_msgs_msg_dds__TFMessage_> tf_, tf_static_;
  Writer<nav_msgs_msg_dds__Path_> path_;
  Writer<sensor_msgs_msg_dds__PointCloud2_> map_points_, dense_map_;
  Writer<visualization_msgs_msg_dds__MarkerArray_> keyframes_;
  Writer<nav_msgs_msg_dds__OccupancyGrid_> occupancy_;
  Writer<sensor_msgs_msg_dds__Image_> mask_, overlay_;
  Writer<std_msgs_msg_dds__String_> state_;
};

}  // namespace lrd_ros2
