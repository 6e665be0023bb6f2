#pragma once
// The part of a ROS node between its subscriptions and lrd::System, whatever its ROS: frames
// queued by the image callbacks (never waiting on tracking or the network), a tracking thread
// that starts the system at the first frame (from the settings' camera or the first camera_info)
// and feeds it, malformed and late frames dropped and counted with throttled warnings, reset and
// save for the node's services, and the outputs written at stop. The ROS 1 and ROS 2 nodes are
// this plus their subscriptions, services and a TopicPublisher.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "lrd/autosave/autosaver.h"
#include "lrd/node/frame_queue.h"
#include "lrd/node/node_params.h"
#include "lrd/node/node_system.h"
#include "lrd/node/topic_publisher.h"

namespace lrd::node {

struct NodeCounts {
  std::size_t received = 0;       // colour/depth pairs the callbacks got (before the stop)
  std::size_t malformed = 0;      // dropped: a malformed or unusable message (warned)
  std::size_t queue_dropped = 0;  // dropped: tracking was slower than the camera
  std::size_t no_camera = 0;      // dropped: no settings and no camera_info yet
  std::size_t tracked = 0, lost = 0, not_initialized = 0;
};

// The node's log, in its ROS's logging.
struct NodeLog {
  std::function<void(const std::string&)> info, warn, error;
};

// A colour/depth pair as the callbacks convert it.
struct NodeFrame {
  cv::Mat rgb, depth;  // BGR, metres
  double timestamp = 0.0;
  std::string frame_id;
  // When the pair was complete in the callback: the node's latency runs from here to the pose.
  std::chrono::steady_clock::time_point arrival = std::chrono::steady_clock::now();
};

class SlamDriver {
 public:
  // on_fatal: the tracking thread met an error it cannot go on from (it logged it): the node
  // shuts its ROS down.
  SlamDriver(NodeParams params, std::shared_ptr<TopicPublisher> publisher, NodeLog log,
             std::function<void()> on_fatal);
  ~SlamDriver();
  SlamDriver(const SlamDriver&) = delete;
  SlamDriver& operator=(const SlamDriver&) = delete;

  [[nodiscard]] const NodeParams& params() const { return params_; }

  // The callbacks' side; any thread, never blocking on tracking.
  void count_received();
  void push(NodeFrame frame);
  void drop(std::size_t NodeCounts::*counter, const std::string& why);
  void set_camera_info(const io::SourceCamera& camera);

  // The services' side. save: the trajectory so far to dir; false (and why) when there is none.
  bool save(const std::filesystem::path& dir, std::string* message);
  void request_reset() { reset_requested_ = true; }

  // Tracks what is queued, stops the system's threads, writes CameraTrajectory.txt,
  // KeyFrameTrajectory.txt, track_times.txt, node_summary.json (the occupancy maps with the dense
  // stage, map.lrdmap with autosave) to output_dir. Idempotent.
  void stop();
  [[nodiscard]] bool failed() const { return failed_.load(); }
  [[nodiscard]] NodeCounts counts() const;

 private:
  void track_frames();  // the tracking thread
  void track(NodeFrame& frame);
  bool start_system(const NodeFrame& first);
  void report_queue_drops(std::chrono::steady_clock::time_point& last_report, std::size_t& reported);
  void save_occupancy(const std::filesystem::path& dir);
  void save_final_map();
  void write_summary(const NodeCounts& counts, std::size_t loops) const;

  const NodeParams params_;
  const bool names_camera_;  // settings or config name the camera: no camera_info needed
  std::shared_ptr<TopicPublisher> publisher_;
  const NodeLog log_;
  const std::function<void()> on_fatal_;

  std::mutex camera_mutex_;
  std::optional<io::SourceCamera> camera_info_;

  mutable std::mutex system_mutex_;  // the system is made by the tracking thread at the first frame
  std::unique_ptr<NodeSystem> system_;
  std::shared_ptr<autosave::Autosaver> autosaver_;  // with the autosave parameter, beside the system
  std::atomic<bool> reset_requested_{false};
  std::atomic<bool> failed_{false};
  double last_timestamp_ = -1.0;

  mutable std::mutex counts_mutex_;
  NodeCounts counts_;
  // The last drop warning of each kind (counter), for the throttle.
  std::vector<std::pair<std::size_t NodeCounts::*, std::chrono::steady_clock::time_point>> last_warning_;
  std::vector<FrameTime> times_;      // the tracking thread's, read after it stopped
  std::vector<double> latencies_ms_;  // arrival to published result, per tracked frame (likewise)

  FrameQueue<NodeFrame> frames_;
  bool stopped_ = false;
  std::thread tracker_;  // last: started once everything above is ready
};

}  // namespace lrd::node
