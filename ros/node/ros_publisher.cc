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

#include <string>

#include "lrd/node/map_messages.h"
#include "lrd_ros/image_messages.h"
#include "lrd_ros/pose_messages.h"

namespace lrd_ros {

namespace {

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

geometry_msgs::Point point_message(const Eigen::Vector3d& v) {
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

}  // namespace

RosPublisher::RosPublisher(ros::NodeHandle& node, lrd::node::PublishSettings settings)
    : TopicPublisher(std::move(settings)),
      pose_(node.advertise<geometry_msgs::PoseStamped>("pose", 10)),
      path_(node.advertise<nav_msgs::Path>("path", 1, true)),
      map_points_(node.advertise<sensor_msgs::PointCloud2>("map_points", 1, true)),
      keyframes_(node.advertise<visualization_msgs::MarkerArray>("keyframes", 1, true)),
      dense_map_(node.advertise<sensor_msgs::PointCloud2>("dense_map", 1, true)),
      occupancy_(node.advertise<nav_msgs::OccupancyGrid>("occupancy", 1, true)),
      mask_(node.advertise<sensor_msgs::Image>("dynamic_mask", 2)),
      overlay_(node.advertise<sensor_msgs::Image>("overlay", 2)),
      state_(node.advertise<std_msgs::String>("state", 1, true)) {
  start();
}

RosPublisher::~RosPublisher() {
  stop_occupancy();  // its thread calls the send_* below
}

void RosPublisher::warn(const std::string& what) {
  ROS_WARN_THROTTLE(10.0, "lrdslam: %s", what.c_str());
}

void RosPublisher::send_static_transform(const std::string& parent, const std::string& child,
                                         const Eigen::Isometry3d& T_parent_child) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time::now();
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform = transform_message(T_parent_child);
  static_tf_.sendTransform(t);
}

void RosPublisher::send_state(const std::string& state) {
  std_msgs::String m;
  m.data = state;
  state_.publish(m);
}

void RosPublisher::send_pose(double stamp, const Eigen::Isometry3d& T) {
  geometry_msgs::PoseStamped pose;
  pose.header.stamp = to_stamp(stamp);
  pose.header.frame_id = settings().map_frame;
  pose.pose = pose_message(T);
  pose_.publish(pose);

  geometry_msgs::TransformStamped t;
  t.header = pose.header;
  t.child_frame_id = camera_frame();
  t.transform = transform_message(T);
  tf_.sendTransform(t);
}

void RosPublisher::send_path(double stamp, const lrd::io::Trajectory& path) {
  nav_msgs::Path m;
  m.header.frame_id = settings().map_frame;
  if (!path.empty()) m.header.stamp = to_stamp(stamp);
  m.poses.reserve(path.size());
  for (const lrd::io::StampedPose& p : path) {
    geometry_msgs::PoseStamped pose;
    pose.header.stamp = to_stamp(p.timestamp);
    pose.header.frame_id = settings().map_frame;
    pose.pose = pose_message(p.pose);
    m.poses.push_back(pose);
  }
  path_.publish(m);
}

void RosPublisher::send_map(const lrd::events::MapSnapshot& map) {
  sensor_msgs::PointCloud2 cloud = cloud_message(map.points.size(), false, settings().map_frame);
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  for (const lrd::events::MapPointSnapshot& p : map.points) {
    *x = static_cast<float>(p.position.x());
    *y = static_cast<float>(p.position.y());
    *z = static_cast<float>(p.position.z());
    ++x, ++y, ++z;
  }
  map_points_.publish(cloud);

  visualization_msgs::Marker m;
  m.header.frame_id = settings().map_frame;
  m.header.stamp = cloud.header.stamp;
  m.ns = "keyframes";
  m.type = visualization_msgs::Marker::LINE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = lrd::node::kKeyframeLineWidth;
  m.color.b = 1.0f;
  m.color.a = 1.0f;
  for (const lrd::events::KeyframePose& k : map.keyframes)
    for (const Eigen::Vector3d& v : lrd::node::frustum_lines(k.T_wc)) m.points.push_back(point_message(v));
  visualization_msgs::MarkerArray markers;
  markers.markers.push_back(m);
  keyframes_.publish(markers);
}

void RosPublisher::send_dense_map(const lrd::dense::PointCloud& dense) {
  const bool colour = dense.colours.size() == dense.points.size();
  sensor_msgs::PointCloud2 cloud = cloud_message(dense.size(), colour, settings().map_frame);
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

void RosPublisher::send_occupancy(const lrd::occupancy::Occupancy& occupancy) {
  const lrd::occupancy::Grid2d& grid = occupancy.grid;
  nav_msgs::OccupancyGrid message;
  message.header.stamp = ros::Time::now();
  message.header.frame_id = settings().map_frame;
  message.info.map_load_time = message.header.stamp;
  message.info.resolution = static_cast<float>(grid.resolution);
  message.info.width = static_cast<std::uint32_t>(grid.width);
  message.info.height = static_cast<std::uint32_t>(grid.height);
  message.info.origin = pose_message(lrd::node::grid_origin(grid));
  message.data.assign(grid.cells.begin(), grid.cells.end());
  occupancy_.publish(message);
}

void RosPublisher::send_mask(double stamp, const cv::Mat& mask) {
  mask_.publish(image_message(mask, to_stamp(stamp), camera_frame()));
}

void RosPublisher::send_overlay(double stamp, const cv::Mat& bgr) {
  overlay_.publish(image_message(bgr, to_stamp(stamp), camera_frame()));
}

}  // namespace lrd_ros
