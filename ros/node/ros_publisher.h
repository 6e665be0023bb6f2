#pragma once
// The node's view of the system: an events::Subscriber (lrd/events) that turns the system's
// events into ROS topics on the node's private namespace. It runs on the system's publisher
// thread, so nothing here is timed as tracking; it reads the system only through its thread-safe
// queries (trajectory, map_snapshot, dense_map). The per-frame results a robot acts on (pose, tf,
// path, state) come from the tracking thread's result instead (publish_result): the publisher
// drops frame events when it falls behind, and a pose must never be dropped.
#include <nav_msgs/Path.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <thread>

#include "lrd/events/event_publisher.h"
#include "lrd/io/trajectory.h"
#include "lrd/system.h"

namespace lrd_ros {

struct PublisherSettings {
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

class RosPublisher final : public lrd::events::Subscriber {
 public:
  RosPublisher(ros::NodeHandle& private_node, PublisherSettings settings);
  // Stops the occupancy thread (after the build it may be in).
  ~RosPublisher() override;
  // The same, before the system it reads goes away (the node's stop). Idempotent; not concurrent
  // with the destructor.
  void stop_occupancy();
  RosPublisher(const RosPublisher&) = delete;
  RosPublisher& operator=(const RosPublisher&) = delete;

  // Before the first frame: the system it may query, and the images' frame_id (the camera frame
  // when ~camera_frame is not set).
  void attach(const lrd::System* system, const std::string& image_frame);

  // The tracking thread, after each frame: pose, tf and path when tracked, state on change.
  void publish_result(double timestamp, const lrd::TrackResult& result);

  // Mask and overlay images (dropped with the frame event when the publisher is behind).
  void on_frame(const lrd::events::FrameTracked& e) override;
  void on_loop(const lrd::events::LoopClosed& e) override;
  void on_map_changed(const lrd::events::MapChanged& e) override;
  void on_dense_map(const lrd::events::DenseMapUpdated& e) override;

  // `path` = this trajectory (after a loop closure, and when the trajectory is saved, so the last
  // path and the saved file agree). Any thread.
  void publish_path(const lrd::io::Trajectory& trajectory);
  // The sparse map and keyframes now, and (with the dense stage) the dense map.
  void publish_map();
  void publish_dense_map();
  // The 2-D occupancy grid now (with the dense stage and occupancy.enabled). Any thread.
  void publish_occupancy();

  // System::reset replaces the map the queries above read: it runs alone (the tracking thread),
  // the queries (this publisher's thread, the node's services) beside each other.
  template <typename F>
  void exclusive(F&& f) {
    std::unique_lock lock(system_mutex_);
    f();
  }
  template <typename F>
  void shared(F&& f) const {
    std::shared_lock lock(system_mutex_);
    f();
  }

 private:
  using Clock = std::chrono::steady_clock;
  void publish_state(const std::string& state);

  const PublisherSettings settings_;
  const lrd::System* system_ = nullptr;
  std::string camera_frame_;
  ros::Publisher pose_, path_, map_points_, keyframes_, dense_map_, occupancy_, mask_, overlay_, state_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;

  mutable std::shared_mutex system_mutex_;
  std::mutex path_mutex_;  // the service thread republishes the path too
  nav_msgs::Path path_message_;
  std::optional<Clock::time_point> last_path_;

  static bool due(const std::optional<Clock::time_point>& last, double period_s);

  std::string last_state_;
  std::optional<Clock::time_point> last_map_, last_dense_;

  // The occupancy grid is built on its own thread (seconds on a long map: casting every keyframe's
  // rays), below tracking's priority, so the publisher thread stays free for the path a loop
  // corrects: a dense update asks for a build, the thread builds at most every
  // occupancy_period_s, from the end of the last build.
  void occupancy_loop();
  std::mutex occupancy_mutex_;
  std::condition_variable occupancy_wake_;
  bool occupancy_wanted_ = false, occupancy_stop_ = false;
  std::thread occupancy_thread_;
};

}  // namespace lrd_ros
