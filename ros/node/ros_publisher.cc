#include "ros_publisher.h"

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/console.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <std_msgs/String.h>
#include <visualization_msgs/MarkerArray.h>

#include <opencv2/imgproc.hpp>
#include <string>

#include "lrd/system.h"
#include "lrd/util/thread_priority.h"
#include "lrd_ros/image_messages.h"
#include "lrd_ros/pose_messages.h"

namespace lrd_ros {

namespace {

// The frame in grey, the dynamic mask tinted blue, the keypoints tracking kept in green and those
// the geometry check removed in red.
cv::Mat overlay_image(const lrd::events::FrameTracked& e) {
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

sensor_msgs::PointCloud2 cloud_message(std::size_t n, bool colour, const std::string& frame) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header.frame_id = frame;
  cloud.header.stamp = ros::Time::now();
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  if (colour)
    modifier.setPointCloud2FieldsByString(2, "xyz", "rgb");
  else
    modifier.setPointCloud2FieldsByString(1, "xyz");
  modifier.resize(n);
  return cloud;
}

// A keyframe as a small camera frustum (rviz: LINE_LIST).
void add_frustum(visualization_msgs::Marker& m, const Eigen::Isometry3d& T) {
  constexpr double w = 0.05, h = 0.0375, z = 0.04;
  const Eigen::Vector3d c = T.translation();
  const Eigen::Vector3d corners[4] = {T * Eigen::Vector3d(-w, -h, z), T * Eigen::Vector3d(w, -h, z),
                                      T * Eigen::Vector3d(w, h, z), T * Eigen::Vector3d(-w, h, z)};
  const auto point = [](const Eigen::Vector3d& v) {
    geometry_msgs::Point p;
    p.x = v.x();
    p.y = v.y();
    p.z = v.z();
    return p;
  };
  for (int i = 0; i < 4; ++i) {
    m.points.push_back(point(c));
    m.points.push_back(point(corners[i]));
    m.points.push_back(point(corners[i]));
    m.points.push_back(point(corners[(i + 1) % 4]));
  }
}

}  // namespace

RosPublisher::RosPublisher(ros::NodeHandle& node, PublisherSettings settings)
    : settings_(std::move(settings)),
      pose_(node.advertise<geometry_msgs::PoseStamped>("pose", 10)),
      path_(node.advertise<nav_msgs::Path>("path", 1, true)),
      map_points_(node.advertise<sensor_msgs::PointCloud2>("map_points", 1, true)),
      keyframes_(node.advertise<visualization_msgs::MarkerArray>("keyframes", 1, true)),
      dense_map_(node.advertise<sensor_msgs::PointCloud2>("dense_map", 1, true)),
      occupancy_(node.advertise<nav_msgs::OccupancyGrid>("occupancy", 1, true)),
      mask_(node.advertise<sensor_msgs::Image>("dynamic_mask", 2)),
      overlay_(node.advertise<sensor_msgs::Image>("overlay", 2)),
      state_(node.advertise<std_msgs::String>("state", 1, true)) {
  path_message_.header.frame_id = settings_.map_frame;
  if (!settings_.world_frame.empty()) {
    // world x = camera z (forward), world y = -camera x (left), world z = -camera y (up).
    Eigen::Isometry3d T_world_map = Eigen::Isometry3d::Identity();
    T_world_map.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = settings_.world_frame;
    t.child_frame_id = settings_.map_frame;
    t.transform = transform_message(T_world_map);
    static_tf_.sendTransform(t);
  }
  occupancy_thread_ = std::thread([this] { occupancy_loop(); });
}

RosPublisher::~RosPublisher() {
  stop_occupancy();
}

void RosPublisher::stop_occupancy() {
  {
    std::lock_guard lock(occupancy_mutex_);
    occupancy_stop_ = true;
  }
  occupancy_wake_.notify_all();
  if (occupancy_thread_.joinable()) occupancy_thread_.join();
}

void RosPublisher::occupancy_loop() {
  (void)lrd::util::lower_this_thread_priority();
  std::unique_lock lock(occupancy_mutex_);
  for (;;) {
    occupancy_wake_.wait(lock, [this] { return occupancy_stop_ || occupancy_wanted_; });
    if (occupancy_stop_) return;
    occupancy_wanted_ = false;
    lock.unlock();
    try {
      publish_occupancy();
    } catch (const std::exception& e) {
      ROS_WARN_THROTTLE(10.0, "lrdslam: occupancy grid not published: %s", e.what());
    }
    lock.lock();
    // The period counts from the end of the build; a stop ends the wait.
    occupancy_wake_.wait_for(lock, std::chrono::duration<double>(settings_.occupancy_period_s),
                             [this] { return occupancy_stop_; });
  }
}

void RosPublisher::attach(const lrd::System* system, const std::string& image_frame) {
  system_ = system;
  camera_frame_ = settings_.camera_frame.empty() ? image_frame : settings_.camera_frame;
  if (camera_frame_.empty()) camera_frame_ = "camera";
}

void RosPublisher::publish_result(double timestamp, const lrd::TrackResult& r) {
  publish_state(std::string(lrd::tracking::to_string(r.state)));
  if (!r.T_wc) return;
  geometry_msgs::PoseStamped pose;
  pose.header.stamp = to_stamp(timestamp);
  pose.header.frame_id = settings_.map_frame;
  pose.pose = pose_message(*r.T_wc);
  pose_.publish(pose);

  geometry_msgs::TransformStamped t;
  t.header = pose.header;
  t.child_frame_id = camera_frame_;
  t.transform = transform_message(*r.T_wc);
  tf_.sendTransform(t);

  // The path grows with the run: re-sent at most once a period, so its cost per frame stays flat.
  std::lock_guard lock(path_mutex_);
  path_message_.header.stamp = pose.header.stamp;
  path_message_.poses.push_back(pose);
  if (!due(last_path_, settings_.path_period_s)) return;
  path_.publish(path_message_);
  last_path_ = Clock::now();
}

void RosPublisher::on_frame(const lrd::events::FrameTracked& e) {
  if (e.grey.empty()) return;
  const ros::Time stamp = to_stamp(e.timestamp);
  if (mask_.getNumSubscribers() > 0) {
    const cv::Mat mask = e.mask.empty() ? cv::Mat::zeros(e.grey.size(), CV_8UC1) : e.mask;
    cv::Mat binary;
    cv::compare(mask, 0, binary, cv::CMP_GT);  // 255 = dynamic
    mask_.publish(image_message(binary, stamp, camera_frame_));
  }
  if (overlay_.getNumSubscribers() > 0)
    overlay_.publish(image_message(overlay_image(e), stamp, camera_frame_));
}

void RosPublisher::publish_state(const std::string& state) {
  if (state == last_state_) return;
  last_state_ = state;
  std_msgs::String m;
  m.data = state;
  state_.publish(m);
}

void RosPublisher::on_loop(const lrd::events::LoopClosed& /*e*/) {
  if (system_ == nullptr) return;
  lrd::io::Trajectory trajectory;
  shared([&] { trajectory = system_->trajectory(); });
  publish_path(trajectory);
  publish_map();
}

bool RosPublisher::due(const std::optional<Clock::time_point>& last, double period_s) {
  return !last || std::chrono::duration<double>(Clock::now() - *last).count() >= period_s;
}

// The throttled clouds count their period from the end of the last one: a cloud that takes longer
// to build than the period (a big map, a slow machine) would otherwise be rebuilt for every queued
// event, and the backlog would outlast the run (seen under ASan on a loaded machine: a node that
// needed minutes to stop).
void RosPublisher::on_map_changed(const lrd::events::MapChanged& /*e*/) {
  if (!due(last_map_, settings_.map_period_s)) return;
  publish_map();
  last_map_ = Clock::now();
}

void RosPublisher::on_dense_map(const lrd::events::DenseMapUpdated& /*e*/) {
  {
    std::lock_guard lock(occupancy_mutex_);
    occupancy_wanted_ = true;
  }
  occupancy_wake_.notify_one();
  if (!due(last_dense_, settings_.dense_period_s)) return;
  publish_dense_map();
  last_dense_ = Clock::now();
}

void RosPublisher::publish_path(const lrd::io::Trajectory& trajectory) {
  std::lock_guard lock(path_mutex_);
  path_message_.poses.clear();
  for (const lrd::io::StampedPose& p : trajectory) {
    geometry_msgs::PoseStamped pose;
    pose.header.stamp = to_stamp(p.timestamp);
    pose.header.frame_id = settings_.map_frame;
    pose.pose = pose_message(p.pose);
    path_message_.poses.push_back(pose);
  }
  if (!path_message_.poses.empty()) path_message_.header.stamp = path_message_.poses.back().header.stamp;
  last_path_ = Clock::now();
  path_.publish(path_message_);
}

void RosPublisher::publish_map() {
  if (system_ == nullptr) return;
  lrd::events::MapSnapshot map;
  shared([&] { map = system_->map_snapshot(); });
  sensor_msgs::PointCloud2 cloud = cloud_message(map.points.size(), false, settings_.map_frame);
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  for (const lrd::events::MapPointSnapshot& p : map.points) {
    *x = static_cast<float>(p.position.x());
    *y = static_cast<float>(p.position.y());
    *z = static_cast<float>(p.position.z());
    ++x, ++y, ++z;
  }
  map_points_.publish(cloud);

  visualization_msgs::Marker m;
  m.header.frame_id = settings_.map_frame;
  m.header.stamp = cloud.header.stamp;
  m.ns = "keyframes";
  m.type = visualization_msgs::Marker::LINE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = 0.005;
  m.color.b = 1.0f;
  m.color.a = 1.0f;
  for (const lrd::events::KeyframePose& k : map.keyframes) add_frustum(m, k.T_wc);
  visualization_msgs::MarkerArray markers;
  markers.markers.push_back(m);
  keyframes_.publish(markers);
}

void RosPublisher::publish_dense_map() {
  if (system_ == nullptr || !system_->dense_enabled()) return;
  lrd::dense::PointCloud dense;
  shared([&] { dense = system_->dense_map(); });
  const bool colour = dense.colours.size() == dense.points.size();
  sensor_msgs::PointCloud2 cloud = cloud_message(dense.size(), colour, settings_.map_frame);
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  for (std::size_t i = 0; i < dense.size(); ++i, ++x, ++y, ++z) {
    *x = dense.points[i].x();
    *y = dense.points[i].y();
    *z = dense.points[i].z();
  }
  if (colour) {
    sensor_msgs::PointCloud2Iterator<std::uint8_t> r(cloud, "r"), g(cloud, "g"), b(cloud, "b");
    for (std::size_t i = 0; i < dense.size(); ++i, ++r, ++g, ++b) {
      *b = dense.colours[i][0];
      *g = dense.colours[i][1];
      *r = dense.colours[i][2];
    }
  }
  dense_map_.publish(cloud);
}

void RosPublisher::publish_occupancy() {
  if (system_ == nullptr || !system_->occupancy_enabled()) return;
  std::optional<lrd::occupancy::Occupancy> occupancy;
  shared([&] { occupancy.emplace(system_->occupancy()); });
  const lrd::occupancy::Grid2d& grid = occupancy->grid;
  nav_msgs::OccupancyGrid message;
  message.header.stamp = ros::Time::now();
  message.header.frame_id = settings_.map_frame;
  message.info.map_load_time = message.header.stamp;
  message.info.resolution = static_cast<float>(grid.resolution);
  message.info.width = static_cast<std::uint32_t>(grid.width);
  message.info.height = static_cast<std::uint32_t>(grid.height);
  // Cell (0, 0)'s corner on the floor, the grid's axes along the floor: the floor frame in the map
  // frame (whose axes are the first camera's, not z-up).
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  origin.linear() = grid.floor.rotation.transpose();
  origin.translation() = grid.floor.to_map(Eigen::Vector3d(grid.origin.x(), grid.origin.y(), 0.0));
  message.info.origin = pose_message(origin);
  message.data.assign(grid.cells.begin(), grid.cells.end());
  occupancy_.publish(message);
}

}  // namespace lrd_ros
