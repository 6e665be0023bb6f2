#pragma once
// What a ROS node publishes and when, whatever its ROS: an events::Subscriber (lrd/events) that
// runs on the system's publisher thread (so nothing here is timed as tracking), reads the system
// only through its thread-safe queries, throttles the costly topics and hands each message's
// content to the ROS-specific send_* of the node's publisher (ROS 1 or ROS 2). The per-frame
// results a robot acts on (pose, tf, path, state) come from the tracking thread's result instead
// (publish_result): the publisher drops frame events when it falls behind, and a pose must never
// be dropped.
#include <Eigen/Geometry>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <thread>

#include "lrd/events/event_publisher.h"
#include "lrd/io/trajectory.h"
#include "lrd/node/node_params.h"
#include "lrd/system.h"

namespace lrd::node {

class TopicPublisher : public events::Subscriber {
 public:
  explicit TopicPublisher(PublishSettings settings);
  ~TopicPublisher() override;
  TopicPublisher(const TopicPublisher&) = delete;
  TopicPublisher& operator=(const TopicPublisher&) = delete;

  // Starts the occupancy thread and publishes the static world -> map transform. The derived
  // publisher calls it once its topics exist.
  void start();
  // Stops the occupancy thread (after the build it may be in), before the system it reads goes
  // away. Idempotent. A derived publisher calls it in its destructor too: the thread calls send_*.
  void stop_occupancy();

  // Before the first frame: the system it may query, and the images' frame_id (the camera frame
  // when camera_frame is not set).
  void attach(const System* system, const std::string& image_frame);

  // The tracking thread, after each frame: pose, tf and path when tracked, state on change.
  void publish_result(double timestamp, const TrackResult& result);

  void on_frame(const events::FrameTracked& e) override;
  void on_loop(const events::LoopClosed& e) override;
  void on_map_changed(const events::MapChanged& e) override;
  void on_dense_map(const events::DenseMapUpdated& e) override;

  // `path` = this trajectory (after a loop closure, and when the trajectory is saved, so the last
  // path and the saved file agree). Any thread.
  void publish_path(const io::Trajectory& trajectory);
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

  [[nodiscard]] const PublishSettings& settings() const { return settings_; }
  [[nodiscard]] const std::string& camera_frame() const { return camera_frame_; }

  // The frame in grey, the dynamic mask tinted blue, the keypoints tracking kept in green and
  // those the geometry check removed in red (the overlay topic).
  [[nodiscard]] static cv::Mat overlay_image(const events::FrameTracked& e);
  // world x = camera z (forward), world y = -camera x (left), world z = -camera y (up).
  [[nodiscard]] static Eigen::Isometry3d world_from_map();

 protected:
  // The messages, in the node's ROS. Stamps in seconds; "now" where a message has no frame's.
  virtual void send_state(const std::string& state) = 0;
  // pose (map frame) and the map -> camera transform on /tf.
  virtual void send_pose(double stamp, const Eigen::Isometry3d& T_map_camera) = 0;
  virtual void send_path(double stamp, const io::Trajectory& path) = 0;
  // map_points and keyframes.
  virtual void send_map(const events::MapSnapshot& map) = 0;
  virtual void send_dense_map(const dense::PointCloud& cloud) = 0;
  virtual void send_occupancy(const occupancy::Occupancy& occupancy) = 0;
  virtual void send_static_transform(const std::string& parent, const std::string& child,
                                     const Eigen::Isometry3d& T_parent_child) = 0;
  // dynamic_mask (255 = dynamic) and overlay, only while someone listens.
  [[nodiscard]] virtual bool mask_wanted() const = 0;
  [[nodiscard]] virtual bool overlay_wanted() const = 0;
  virtual void send_mask(double stamp, const cv::Mat& mask) = 0;
  virtual void send_overlay(double stamp, const cv::Mat& bgr) = 0;
  // A send_* that failed on the occupancy thread (logged by the node, throttled).
  virtual void warn(const std::string& what) = 0;

 private:
  using Clock = std::chrono::steady_clock;
  static bool due(const std::optional<Clock::time_point>& last, double period_s);
  void publish_state(const std::string& state);
  void occupancy_loop();

  const PublishSettings settings_;
  const System* system_ = nullptr;
  std::string camera_frame_;

  mutable std::shared_mutex system_mutex_;
  std::mutex path_mutex_;  // the service thread republishes the path too
  io::Trajectory path_;
  std::optional<Clock::time_point> last_path_;

  std::string last_state_;
  std::optional<Clock::time_point> last_map_, last_dense_;

  // The occupancy grid is built on its own thread (seconds on a long map: casting every keyframe's
  // rays), below tracking's priority, so the publisher thread stays free for the path a loop
  // corrects: a dense update asks for a build, the thread builds at most every
  // occupancy_period_s, from the end of the last build.
  std::mutex occupancy_mutex_;
  std::condition_variable occupancy_wake_;
  bool occupancy_wanted_ = false, occupancy_stop_ = false;
  std::thread occupancy_thread_;
};

}  // namespace lrd::node
