#pragma once
// lrdslam_ros: lrd-slam as a ROS 1 node, a thin adapter over lrd::System: roscpp subscriptions
// (colour and depth paired by message_filters) and services around lrd::node::SlamDriver (frame
// queue, tracking thread, drops, outputs), RosPublisher for the topics.
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <ros/node_handle.h>
#include <ros/service_server.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_srvs/Trigger.h>

#include <memory>

#include "lrd/node/node_params.h"
#include "lrd/node/slam_driver.h"
#include "ros_publisher.h"

namespace lrd_ros {

// The private parameters (~rgb_topic, ...) in the shared table.
[[nodiscard]] lrd::node::NodeParams read_params(const ros::NodeHandle& private_node);

class SlamNode {
 public:
  SlamNode(ros::NodeHandle& node, ros::NodeHandle& private_node);
  SlamNode(const SlamNode&) = delete;
  SlamNode& operator=(const SlamNode&) = delete;

  // SlamDriver::stop: tracks what is queued, writes the outputs to ~output_dir. Idempotent.
  void stop() { driver_.stop(); }
  // The tracking thread met an error it cannot go on from (it logged it and shut ROS down).
  [[nodiscard]] bool failed() const { return driver_.failed(); }

 private:
  using Policy = message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::Image>;

  void on_images(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth);
  void on_camera_info(const sensor_msgs::CameraInfoConstPtr& info);
  bool on_save_trajectory(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool on_reset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);

  const lrd::node::NodeParams params_;
  std::shared_ptr<RosPublisher> publisher_;
  lrd::node::SlamDriver driver_;
  message_filters::Subscriber<sensor_msgs::Image> rgb_sub_, depth_sub_;
  message_filters::Synchronizer<Policy> sync_;
  ros::Subscriber camera_info_sub_;
  ros::ServiceServer save_service_, reset_service_;
};

}  // namespace lrd_ros
