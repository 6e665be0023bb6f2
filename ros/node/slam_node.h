#pragma once
// lrdslam_ros: lrd-slam as a ROS 1 node, a thin adapter over lrd::System. The image callback only
// checks and converts a colour/depth pair and queues it (never waiting on tracking or the network);
// a tracking thread feeds the system; RosPublisher turns the system's events into topics.
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <ros/node_handle.h>
#include <ros/service_server.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_srvs/Trigger.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "frame_queue.h"
#include "node_config.h"
#include "ros_publisher.h"

namespace lrd_ros {

struct NodeParams {
  std::string rgb_topic = "/camera/rgb/image_color";
  std::string depth_topic = "/camera/depth/image";
  std::string camera_info_topic = "/camera/rgb/camera_info";
  NodeSettings system;
  PublisherSettings publisher;
  int queue_size = 2;  // frames waiting for tracking (the oldest dropped beyond) and sync queue
  std::filesystem::path output_dir = "lrdslam_output";
  double warn_period_s = 5.0;  // throttle of the drop warnings

  // The private parameters (~rgb_topic, ...); throws lrd::Error for a value out of range.
  static NodeParams from(const ros::NodeHandle& private_node);
};

struct NodeCounts {
  std::size_t received = 0;       // colour/depth pairs the callback got
  std::size_t malformed = 0;      // dropped: a malformed or unusable message (warned)
  std::size_t queue_dropped = 0;  // dropped: tracking was slower than the camera
  std::size_t no_camera = 0;      // dropped: no ~settings and no camera_info yet
  std::size_t tracked = 0, lost = 0, not_initialized = 0;
};

class SlamNode {
 public:
  SlamNode(ros::NodeHandle& node, ros::NodeHandle& private_node);
  ~SlamNode();
  SlamNode(const SlamNode&) = delete;
  SlamNode& operator=(const SlamNode&) = delete;

  // Tracks what is queued, stops the system's threads, writes CameraTrajectory.txt,
  // KeyFrameTrajectory.txt, track_times.txt and node_summary.json to ~output_dir. Idempotent.
  void stop();
  // The tracking thread met an error it cannot go on from (it logged it and shut ROS down).
  [[nodiscard]] bool failed() const { return failed_.load(); }

 private:
  struct Frame {
    cv::Mat rgb, depth;  // BGR, metres
    double timestamp = 0.0;
    std::string frame_id;
  };
  using Policy = message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::Image>;

  void on_images(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth);
  void on_camera_info(const sensor_msgs::CameraInfoConstPtr& info);
  bool on_save_trajectory(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool on_reset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);

  void track_frames();  // the tracking thread
  void track(Frame& frame);
  bool start_system(const Frame& first);
  void drop(std::size_t NodeCounts::*counter, const std::string& why);
  void save(const std::filesystem::path& dir, std::string* message);
  // occupancy.bt and occupancy_2d.pgm/.yaml/.png into dir (with the dense stage), at stop.
  void save_occupancy(const std::filesystem::path& dir);

  const NodeParams params_;
  const bool names_camera_;  // ~settings or ~config name the camera: no camera_info needed
  std::shared_ptr<RosPublisher> publisher_;
  message_filters::Subscriber<sensor_msgs::Image> rgb_sub_, depth_sub_;
  message_filters::Synchronizer<Policy> sync_;
  ros::Subscriber camera_info_sub_;
  ros::ServiceServer save_service_, reset_service_;

  std::mutex camera_mutex_;
  std::optional<lrd::io::SourceCamera> camera_info_;

  mutable std::mutex system_mutex_;  // the system is made by the tracking thread at the first frame
  std::unique_ptr<NodeSystem> system_;
  std::atomic<bool> reset_requested_{false};
  std::atomic<bool> failed_{false};
  double last_timestamp_ = -1.0;

  mutable std::mutex counts_mutex_;
  NodeCounts counts_;
  // The last drop warning of each kind (counter), for the throttle.
  std::vector<std::pair<std::size_t NodeCounts::*, std::chrono::steady_clock::time_point>> last_warning_;
  std::vector<FrameTime> times_;  // the tracking thread's, read after it stopped

  FrameQueue<Frame> frames_;
  bool stopped_ = false;
  std::thread tracker_;  // last: started once everything above is ready
};

}  // namespace lrd_ros
