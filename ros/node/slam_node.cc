#include "slam_node.h"

#include <fmt/format.h>
#include <ros/console.h>
#include <ros/ros.h>

#include <algorithm>
#include <cstdint>

#include "lrd/util/error.h"
#include "lrd_ros/image_messages.h"

namespace lrd_ros {

namespace {

// roscpp's subscription queue drops the oldest message without a word when the spinner falls
// behind (a loaded machine: CI lost 5 of 150 pairs there). The callback only converts and
// queues, so a second of camera here means frames are only ever dropped in the driver, counted.
constexpr std::uint32_t kTransportQueueMessages = 30;

class RosParams final : public lrd::node::ParamReader {
 public:
  explicit RosParams(const ros::NodeHandle& node) : node_(node) {}
  void get(const std::string& name, std::string& value) const override { read(name, value); }
  void get(const std::string& name, bool& value) const override { read(name, value); }
  void get(const std::string& name, int& value) const override { read(name, value); }
  void get(const std::string& name, double& value) const override { read(name, value); }
  [[nodiscard]] std::string display(const std::string& name) const override { return "~" + name; }

 private:
  template <typename T>
  void read(const std::string& name, T& value) const {
    if (!node_.hasParam(name)) return;
    if (!node_.getParam(name, value)) throw lrd::Error(fmt::format("~{} has a value of another type", name));
  }
  const ros::NodeHandle& node_;
};

lrd::node::NodeLog ros_log() {
  return {[](const std::string& m) { ROS_INFO("lrdslam: %s", m.c_str()); },
          [](const std::string& m) { ROS_WARN("lrdslam: %s", m.c_str()); },
          [](const std::string& m) { ROS_FATAL("lrdslam: %s", m.c_str()); }};
}

}  // namespace

lrd::node::NodeParams read_params(const ros::NodeHandle& private_node) {
  return lrd::node::NodeParams::from(RosParams(private_node));
}

SlamNode::SlamNode(ros::NodeHandle& node, ros::NodeHandle& private_node)
    : params_(read_params(private_node)),
      publisher_(std::make_shared<RosPublisher>(private_node, params_.publish)),
      driver_(params_, publisher_, ros_log(), [] { ros::shutdown(); }),
      rgb_sub_(node, params_.rgb_topic, kTransportQueueMessages),
      depth_sub_(node, params_.depth_topic, kTransportQueueMessages),
      sync_(Policy(std::max(params_.queue_size, 2) * 5), rgb_sub_, depth_sub_) {
  sync_.registerCallback(
      boost::bind(&SlamNode::on_images, this, boost::placeholders::_1, boost::placeholders::_2));
  camera_info_sub_ = node.subscribe(params_.camera_info_topic, 1, &SlamNode::on_camera_info, this);
  save_service_ = private_node.advertiseService("save_trajectory", &SlamNode::on_save_trajectory, this);
  reset_service_ = private_node.advertiseService("reset", &SlamNode::on_reset, this);
  ROS_INFO(
      "lrdslam: colour %s, depth %s, camera %s; output to %s", params_.rgb_topic.c_str(),
      params_.depth_topic.c_str(),
      params_.system.settings.empty() ? params_.camera_info_topic.c_str() : params_.system.settings.c_str(),
      params_.output_dir.c_str());
}

void SlamNode::on_images(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth) {
  driver_.count_received();
  lrd::node::NodeFrame f;
  try {
    f.rgb = colour_from_message(*rgb);
  } catch (const std::exception& e) {  // lrd::Error; anything else is no reason to stop the node
    return driver_.drop(&lrd::node::NodeCounts::malformed, params_.rgb_topic + ": " + e.what());
  }
  try {
    f.depth = depth_from_message(*depth);
  } catch (const std::exception& e) {
    return driver_.drop(&lrd::node::NodeCounts::malformed, params_.depth_topic + ": " + e.what());
  }
  if (f.rgb.size() != f.depth.size())
    return driver_.drop(&lrd::node::NodeCounts::malformed,
                        fmt::format("{} is {}x{} but {} is {}x{}", params_.rgb_topic, f.rgb.cols, f.rgb.rows,
                                    params_.depth_topic, f.depth.cols, f.depth.rows));
  f.timestamp = to_seconds(rgb->header.stamp);
  f.frame_id = rgb->header.frame_id;
  driver_.push(std::move(f));
}

void SlamNode::on_camera_info(const sensor_msgs::CameraInfoConstPtr& info) {
  try {
    lrd::io::SourceCamera c = camera_from_message(*info);
    c.origin = "camera_info " + params_.camera_info_topic;
    driver_.set_camera_info(c);
  } catch (const lrd::Error& e) {
    ROS_WARN_THROTTLE(params_.warn_period_s, "lrdslam: ignored a camera_info on %s: %s",
                      params_.camera_info_topic.c_str(), e.what());
  }
}

bool SlamNode::on_save_trajectory(std_srvs::Trigger::Request& /*request*/,
                                  std_srvs::Trigger::Response& response) {
  try {
    response.success = driver_.save(params_.output_dir, &response.message);
  } catch (const std::exception& e) {
    response.success = false;
    response.message = e.what();
  }
  return true;
}

bool SlamNode::on_reset(std_srvs::Trigger::Request& /*request*/, std_srvs::Trigger::Response& response) {
  driver_.request_reset();
  response.success = true;
  response.message = "a new map starts with the next frame";
  return true;
}

}  // namespace lrd_ros
