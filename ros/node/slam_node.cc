#include "slam_node.h"

#include <fmt/format.h>
#include <ros/console.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "lrd/util/error.h"
#include "lrd_ros/image_messages.h"

namespace lrd_ros {

namespace fs = std::filesystem;

namespace {
// roscpp's subscription queue drops the oldest message without a word when the spinner falls
// behind (a loaded machine: CI lost 5 of 150 pairs there). The callback only converts and
// queues, so a second of camera here means frames are only ever dropped in frames_, counted.
constexpr std::uint32_t kTransportQueueMessages = 30;
}  // namespace

NodeParams NodeParams::from(const ros::NodeHandle& pn) {
  NodeParams p;
  pn.param("rgb_topic", p.rgb_topic, p.rgb_topic);
  pn.param("depth_topic", p.depth_topic, p.depth_topic);
  pn.param("camera_info_topic", p.camera_info_topic, p.camera_info_topic);
  pn.param("settings", p.system.settings, p.system.settings);
  pn.param("config", p.system.config, p.system.config);
  pn.param("mode", p.system.mode, p.system.mode);
  pn.param("segmenter", p.system.segmenter, p.system.segmenter);
  pn.param("segmenter_model", p.system.segmenter_model, p.system.segmenter_model);
  pn.param("dense", p.system.dense, p.system.dense);
  pn.param("map_frame", p.publisher.map_frame, p.publisher.map_frame);
  pn.param("camera_frame", p.publisher.camera_frame, p.publisher.camera_frame);
  pn.param("world_frame", p.publisher.world_frame, p.publisher.world_frame);
  pn.param("queue_size", p.queue_size, p.queue_size);
  std::string out = p.output_dir.string();
  pn.param("output_dir", out, out);
  p.output_dir = out;
  if (p.queue_size < 1 || p.queue_size > 1000)
    throw lrd::Error(fmt::format("~queue_size must be 1..1000, got {}", p.queue_size));
  if (p.publisher.map_frame.empty()) throw lrd::Error("~map_frame must not be empty");
  return p;
}

SlamNode::SlamNode(ros::NodeHandle& node, ros::NodeHandle& private_node)
    : params_(NodeParams::from(private_node)),
      // Read once: an unreadable ~config stops the node now, not at the first frame.
      names_camera_(names_camera(params_.system)),
      publisher_(std::make_shared<RosPublisher>(private_node, params_.publisher)),
      rgb_sub_(node, params_.rgb_topic, kTransportQueueMessages),
      depth_sub_(node, params_.depth_topic, kTransportQueueMessages),
      sync_(Policy(std::max(params_.queue_size, 2) * 5), rgb_sub_, depth_sub_),
      frames_(static_cast<std::size_t>(params_.queue_size)) {
  sync_.registerCallback(
      boost::bind(&SlamNode::on_images, this, boost::placeholders::_1, boost::placeholders::_2));
  camera_info_sub_ = node.subscribe(params_.camera_info_topic, 1, &SlamNode::on_camera_info, this);
  save_service_ = private_node.advertiseService("save_trajectory", &SlamNode::on_save_trajectory, this);
  reset_service_ = private_node.advertiseService("reset", &SlamNode::on_reset, this);
  tracker_ = std::thread([this] { track_frames(); });
  ROS_INFO(
      "lrdslam: colour %s, depth %s, camera %s; output to %s", params_.rgb_topic.c_str(),
      params_.depth_topic.c_str(),
      params_.system.settings.empty() ? params_.camera_info_topic.c_str() : params_.system.settings.c_str(),
      params_.output_dir.c_str());
}

SlamNode::~SlamNode() {
  try {
    stop();
  } catch (const std::exception& e) {
    ROS_ERROR("lrdslam: %s", e.what());
  }
}

void SlamNode::drop(std::size_t NodeCounts::*counter, const std::string& why) {
  // Throttled per kind, by hand: ROS_WARN_THROTTLE keeps one unguarded time per call site, and
  // two threads (the image callback, tracking) come here.
  std::size_t n = 0;
  bool warn = false;
  {
    std::lock_guard lock(counts_mutex_);
    n = ++(counts_.*counter);
    const auto now = std::chrono::steady_clock::now();
    auto last = std::find_if(last_warning_.begin(), last_warning_.end(),
                             [counter](const auto& w) { return w.first == counter; });
    if (last == last_warning_.end()) {
      last_warning_.emplace_back(counter, now);
      warn = true;
    } else if (std::chrono::duration<double>(now - last->second).count() >= params_.warn_period_s) {
      last->second = now;
      warn = true;
    }
  }
  if (warn) ROS_WARN("lrdslam: dropped a frame (%zu so far of this kind): %s", n, why.c_str());
}

void SlamNode::on_images(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth) {
  {
    std::lock_guard lock(counts_mutex_);
    ++counts_.received;
  }
  Frame f;
  try {
    f.rgb = colour_from_message(*rgb);
  } catch (const std::exception& e) {  // lrd::Error; anything else is no reason to stop the node
    return drop(&NodeCounts::malformed, params_.rgb_topic + ": " + e.what());
  }
  try {
    f.depth = depth_from_message(*depth);
  } catch (const std::exception& e) {
    return drop(&NodeCounts::malformed, params_.depth_topic + ": " + e.what());
  }
  if (f.rgb.size() != f.depth.size())
    return drop(&NodeCounts::malformed,
                fmt::format("{} is {}x{} but {} is {}x{}", params_.rgb_topic, f.rgb.cols, f.rgb.rows,
                            params_.depth_topic, f.depth.cols, f.depth.rows));
  f.timestamp = to_seconds(rgb->header.stamp);
  f.frame_id = rgb->header.frame_id;
  frames_.push(std::move(f));
}

void SlamNode::on_camera_info(const sensor_msgs::CameraInfoConstPtr& info) {
  try {
    lrd::io::SourceCamera c = camera_from_message(*info);
    c.origin = "camera_info " + params_.camera_info_topic;
    std::lock_guard lock(camera_mutex_);
    camera_info_ = c;
  } catch (const lrd::Error& e) {
    ROS_WARN_THROTTLE(params_.warn_period_s, "lrdslam: ignored a camera_info on %s: %s",
                      params_.camera_info_topic.c_str(), e.what());
  }
}

bool SlamNode::start_system(const Frame& first) {
  std::optional<lrd::io::SourceCamera> info;
  {
    std::lock_guard lock(camera_mutex_);
    info = camera_info_;
  }
  if (!names_camera_ && !info) {
    drop(&NodeCounts::no_camera,
         "no camera yet: no camera_info on " + params_.camera_info_topic + " and no ~settings");
    return false;
  }
  auto system = std::make_unique<NodeSystem>(make_system(params_.system, info));
  system->system->subscribe(publisher_);
  publisher_->attach(system->system.get(), first.frame_id);
  ROS_INFO("lrdslam: camera from %s; %s", system->camera_source.c_str(), system->description.c_str());
  std::lock_guard lock(system_mutex_);
  system_ = std::move(system);
  return true;
}

void SlamNode::track(Frame& f) {
  if (!system_ && !start_system(f)) return;
  lrd::System& slam = *system_->system;
  if (reset_requested_.exchange(false)) {
    publisher_->exclusive([&] { slam.reset(); });
    publisher_->publish_path({});
    last_timestamp_ = -1.0;
    ROS_INFO("lrdslam: reset: a new map starts with this frame");
  }
  if (f.timestamp <= last_timestamp_)
    return drop(&NodeCounts::malformed, fmt::format("stamp {:.6f} is not after the previous frame's {:.6f}",
                                                    f.timestamp, last_timestamp_));
  const lrd::camera::PinholeCamera& camera = system_->camera;
  if (f.rgb.cols != camera.width || f.rgb.rows != camera.height)
    return drop(&NodeCounts::malformed,
                fmt::format("image is {}x{}, the camera ({}) is {}x{}", f.rgb.cols, f.rgb.rows,
                            system_->camera_source, camera.width, camera.height));
  if (camera.rgb_order) cv::cvtColor(f.rgb, f.rgb, cv::COLOR_BGR2RGB);
  last_timestamp_ = f.timestamp;
  lrd::TrackResult r = slam.track_rgbd(f.rgb, f.depth, f.timestamp);
  publisher_->publish_result(f.timestamp, r);
  r.dynamic.mask.release();
  times_.push_back({times_.size(), f.timestamp, r});
  std::lock_guard lock(counts_mutex_);
  if (r.state == lrd::TrackingState::Ok)
    ++counts_.tracked;
  else if (r.state == lrd::TrackingState::Lost)
    ++counts_.lost;
  else
    ++counts_.not_initialized;
}

void SlamNode::track_frames() {
  auto last_report = std::chrono::steady_clock::now();
  std::size_t reported = 0;
  while (auto f = frames_.pop()) {
    // Frames dropped because tracking is slower than the camera: said every warn period.
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_report).count() >= params_.warn_period_s) {
      const std::size_t dropped = frames_.dropped();
      if (dropped > reported)
        ROS_WARN(
            "lrdslam: dropped %zu frames in the last %.0f s (%zu in all): tracking is slower than the camera",
            dropped - reported, params_.warn_period_s, dropped);
      reported = dropped;
      last_report = now;
    }
    try {
      track(*f);
    } catch (const std::exception& e) {
      // A worker thread failed, or settings the node cannot run with: nothing to go on with.
      ROS_FATAL("lrdslam: %s", e.what());
      failed_ = true;
      ros::shutdown();
      return;
    }
  }
}

void SlamNode::save(const fs::path& dir, std::string* message) {
  std::lock_guard lock(system_mutex_);
  if (!system_) {
    *message = "no frames tracked yet";
    return;
  }
  fs::create_directories(dir);
  lrd::io::Trajectory trajectory;
  publisher_->shared([&] {
    trajectory = system_->system->trajectory();
    lrd::io::write_trajectory_tum(dir / "CameraTrajectory.txt", trajectory);
    system_->system->save_keyframe_trajectory_tum(dir / "KeyFrameTrajectory.txt");
  });
  publisher_->publish_path(trajectory);  // the last path is the saved trajectory
  *message = fmt::format("{} poses to {}", trajectory.size(), (dir / "CameraTrajectory.txt").string());
}

void SlamNode::save_occupancy(const fs::path& dir) {
  const lrd::System& system = *system_->system;
  if (!system.occupancy_enabled()) return;
  // The maps a planner loads next time (map_server), from the final keyframe poses.
  try {
    std::vector<Eigen::Vector3d> path;
    for (const lrd::io::StampedPose& p : system.trajectory()) path.push_back(p.pose.translation());
    lrd::occupancy::write_occupancy(system.occupancy(), system.occupancy_params(), path, dir);
  } catch (const std::exception& e) {
    ROS_ERROR("lrdslam: occupancy map not written: %s", e.what());
  }
}

bool SlamNode::on_save_trajectory(std_srvs::Trigger::Request& /*request*/,
                                  std_srvs::Trigger::Response& response) {
  try {
    save(params_.output_dir, &response.message);
    response.success = response.message != "no frames tracked yet";
  } catch (const std::exception& e) {
    response.success = false;
    response.message = e.what();
  }
  return true;
}

bool SlamNode::on_reset(std_srvs::Trigger::Request& /*request*/, std_srvs::Trigger::Response& response) {
  reset_requested_ = true;
  response.success = true;
  response.message = "a new map starts with the next frame";
  return true;
}

void SlamNode::stop() {
  if (stopped_) return;
  stopped_ = true;
  publisher_->stop_occupancy();  // its thread reads the system, which ends after this
  frames_.close();
  if (tracker_.joinable()) tracker_.join();
  NodeCounts counts;
  {
    std::lock_guard lock(counts_mutex_);
    counts = counts_;
    counts.queue_dropped = frames_.dropped();
  }
  std::string saved = "no frames tracked";
  std::size_t loops = 0;
  std::exception_ptr error;  // a worker thread's, rethrown once everything is written
  if (system_) {
    try {
      system_->system->shutdown();
    } catch (...) {
      error = std::current_exception();
    }
    save(params_.output_dir, &saved);
    loops = system_->system->map_stats().loops;
    save_occupancy(params_.output_dir);
  }
  fs::create_directories(params_.output_dir);
  write_track_times(params_.output_dir / "track_times.txt", times_);
  const nlohmann::json summary = {{"received", counts.received},
                                  {"malformed", counts.malformed},
                                  {"queue_dropped", counts.queue_dropped},
                                  {"no_camera", counts.no_camera},
                                  {"tracked", counts.tracked},
                                  {"lost", counts.lost},
                                  {"not_initialized", counts.not_initialized},
                                  {"loops", loops}};
  std::ofstream(params_.output_dir / "node_summary.json") << summary.dump(2) << "\n";
  ROS_INFO(
      "lrdslam: stopped: %zu pairs received, %zu tracked, %zu lost, dropped %zu (tracking behind), %zu "
      "(malformed), %zu (no camera); %s",
      counts.received, counts.tracked, counts.lost, counts.queue_dropped, counts.malformed, counts.no_camera,
      saved.c_str());
  if (error) std::rethrow_exception(error);
}

}  // namespace lrd_ros
