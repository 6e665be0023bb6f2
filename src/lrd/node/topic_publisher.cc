#include "lrd/node/topic_publisher.h"

#include <opencv2/imgproc.hpp>

#include "lrd/util/thread_priority.h"

namespace lrd::node {

TopicPublisher::TopicPublisher(PublishSettings settings) : settings_(std::move(settings)) {}

TopicPublisher::~TopicPublisher() {
  stop_occupancy();
}

void TopicPublisher::start() {
  if (!settings_.world_frame.empty())
    send_static_transform(settings_.world_frame, settings_.map_frame, world_from_map());
  occupancy_thread_ = std::thread([this] { occupancy_loop(); });
}

Eigen::Isometry3d TopicPublisher::world_from_map() {
  Eigen::Isometry3d T_world_map = Eigen::Isometry3d::Identity();
  T_world_map.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return T_world_map;
}

cv::Mat TopicPublisher::overlay_image(const events::FrameTracked& e) {
  cv::Mat bgr;
  cv::cvtColor(e.grey, bgr, cv::COLOR_GRAY2BGR);
  if (!e.mask.empty()) {
    cv::Mat tinted = bgr.clone();
    tinted.setTo(cv::Scalar(255, 64, 0), e.mask);
    cv::addWeighted(bgr, 0.55, tinted, 0.45, 0.0, bgr);
  }
  for (const cv::Point2f& p : e.kept_keypoints) cv::circle(bgr, p, 3, cv::Scalar(0, 220, 0), 1, cv::LINE_AA);
  for (const cv::Point2f& p : e.removed_keypoints)
    cv::circle(bgr, p, 3, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
  return bgr;
}

void TopicPublisher::stop_occupancy() {
  {
    std::lock_guard lock(occupancy_mutex_);
    occupancy_stop_ = true;
  }
  occupancy_wake_.notify_all();
  if (occupancy_thread_.joinable()) occupancy_thread_.join();
}

void TopicPublisher::occupancy_loop() {
  (void)util::lower_this_thread_priority();
  std::unique_lock lock(occupancy_mutex_);
  for (;;) {
    occupancy_wake_.wait(lock, [this] { return occupancy_stop_ || occupancy_wanted_; });
    if (occupancy_stop_) return;
    occupancy_wanted_ = false;
    lock.unlock();
    try {
      publish_occupancy();
    } catch (const std::exception& e) {
      warn(std::string("occupancy grid not published: ") + e.what());
    }
    lock.lock();
    // The period counts from the end of the build; a stop ends the wait.
    occupancy_wake_.wait_for(lock, std::chrono::duration<double>(settings_.occupancy_period_s),
                             [this] { return occupancy_stop_; });
  }
}

void TopicPublisher::attach(const System* system, const std::string& image_frame) {
  system_ = system;
  camera_frame_ = settings_.camera_frame.empty() ? image_frame : settings_.camera_frame;
  if (camera_frame_.empty()) camera_frame_ = "camera";
}

void TopicPublisher::publish_result(double timestamp, const TrackResult& r) {
  publish_state(std::string(tracking::to_string(r.state)));
  if (!r.T_wc) return;
  send_pose(timestamp, *r.T_wc);
  // The path grows with the run: re-sent at most once a period, so its cost per frame stays flat.
  std::lock_guard lock(path_mutex_);
  path_.push_back({timestamp, *r.T_wc});
  if (!due(last_path_, settings_.path_period_s)) return;
  send_path(timestamp, path_);
  last_path_ = Clock::now();
}

void TopicPublisher::on_frame(const events::FrameTracked& e) {
  if (e.grey.empty()) return;
  if (mask_wanted()) {
    const cv::Mat mask = e.mask.empty() ? cv::Mat::zeros(e.grey.size(), CV_8UC1) : e.mask;
    cv::Mat binary;
    cv::compare(mask, 0, binary, cv::CMP_GT);  // 255 = dynamic
    send_mask(e.timestamp, binary);
  }
  if (overlay_wanted()) send_overlay(e.timestamp, overlay_image(e));
}

void TopicPublisher::publish_state(const std::string& state) {
  if (state == last_state_) return;
  last_state_ = state;
  send_state(state);
}

void TopicPublisher::on_loop(const events::LoopClosed& /*e*/) {
  if (system_ == nullptr) return;
  io::Trajectory trajectory;
  shared([&] { trajectory = system_->trajectory(); });
  publish_path(trajectory);
  publish_map();
}

bool TopicPublisher::due(const std::optional<Clock::time_point>& last, double period_s) {
  return !last || std::chrono::duration<double>(Clock::now() - *last).count() >= period_s;
}

// The throttled clouds count their period from the end of the last one: a cloud that takes longer
// to build than the period (a big map, a slow machine) would otherwise be rebuilt for every queued
// event, and the backlog would outlast the run (seen under ASan on a loaded machine: a node that
// needed minutes to stop).
void TopicPublisher::on_map_changed(const events::MapChanged& /*e*/) {
  if (!due(last_map_, settings_.map_period_s)) return;
  publish_map();
  last_map_ = Clock::now();
}

void TopicPublisher::on_dense_map(const events::DenseMapUpdated& /*e*/) {
  {
    std::lock_guard lock(occupancy_mutex_);
    occupancy_wanted_ = true;
  }
  occupancy_wake_.notify_one();
  if (!due(last_dense_, settings_.dense_period_s)) return;
  publish_dense_map();
  last_dense_ = Clock::now();
}

void TopicPublisher::publish_path(const io::Trajectory& trajectory) {
  std::lock_guard lock(path_mutex_);
  path_ = trajectory;
  last_path_ = Clock::now();
  send_path(path_.empty() ? 0.0 : path_.back().timestamp, path_);
}

void TopicPublisher::publish_map() {
  if (system_ == nullptr) return;
  events::MapSnapshot map;
  shared([&] { map = system_->map_snapshot(); });
  send_map(map);
}

void TopicPublisher::publish_dense_map() {
  if (system_ == nullptr || !system_->dense_enabled()) return;
  dense::PointCloud dense;
  shared([&] { dense = system_->dense_map(); });
  send_dense_map(dense);
}

void TopicPublisher::publish_occupancy() {
  if (system_ == nullptr || !system_->occupancy_enabled()) return;
  std::optional<occupancy::Occupancy> occupancy;
  shared([&] { occupancy.emplace(system_->occupancy()); });
  send_occupancy(*occupancy);
}

}  // namespace lrd::node
