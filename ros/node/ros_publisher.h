#pragma once
// The ROS 1 node's topics on its private namespace: lrd::node::TopicPublisher (what is published
// and when) with roscpp publishers and tf2 broadcasters as its messages.
#include <nav_msgs/Path.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <string>

#include "lrd/node/topic_publisher.h"

namespace lrd_ros {

class RosPublisher final : public lrd::node::TopicPublisher {
 public:
  RosPublisher(ros::NodeHandle& private_node, lrd::node::PublishSettings settings);
  ~RosPublisher() override;

 private:
  void send_state(const std::string& state) override;
  void send_pose(double stamp, const Eigen::Isometry3d& T_map_camera) override;
  void send_path(double stamp, const lrd::io::Trajectory& path) override;
  void send_map(const lrd::events::MapSnapshot& map) override;
  void send_dense_map(const lrd::dense::PointCloud& cloud) override;
  void send_occupancy(const lrd::occupancy::Occupancy& occupancy) override;
  void send_static_transform(const std::string& parent, const std::string& child,
                             const Eigen::Isometry3d& T_parent_child) override;
  [[nodiscard]] bool mask_wanted() const override { return mask_.getNumSubscribers() > 0; }
  [[nodiscard]] bool overlay_wanted() const override { return overlay_.getNumSubscribers() > 0; }
  void send_mask(double stamp, const cv::Mat& mask) override;
  void send_overlay(double stamp, const cv::Mat& bgr) override;
  void warn(const std::string& what) override;

  ros::Publisher pose_, path_, map_points_, keyframes_, dense_map_, occupancy_, mask_, overlay_, state_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
};

}  // namespace lrd_ros
