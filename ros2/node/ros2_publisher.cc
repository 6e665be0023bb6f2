#include "ros2_publisher.h"

#include <chrono>
#include <vector>

#include "messages.h"
#include "visualization_msgs.h"

namespace lrd_ros2 {

namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

template <typename T>
void set_sequence(T& seq, void* buffer, std::size_t n) {
  seq._length = seq._maximum = static_cast<std::uint32_t>(n);
  seq._buffer = static_cast<decltype(seq._buffer)>(buffer);
  seq._release = false;
}

// The keyframes' frustums as one LINE_LIST marker.
visualization_msgs_msg_dds__Marker_ keyframe_marker(const std::string& frame, double now,
                                                    std::vector<geometry_msgs_msg_dds__Point_>& points) {
  static const std::string ns = "keyframes", empty;
  visualization_msgs_msg_dds__Marker_ m{};
  m.header = header(now, frame);
  m.ns = text(ns);
  m.type = 5;    // LINE_LIST
  m.action = 0;  // ADD
  m.pose.orientation.w = 1.0;
  m.scale.x = lrd::node::kKeyframeLineWidth;
  m.color.b = 1.0f;
  m.color.a = 1.0f;
  set_sequence(m.points, points.data(), points.size());
  for (char** s : {&m.texture_resource, &m.texture.header.frame_id, &m.texture.format, &m.text,
                   &m.mesh_resource, &m.mesh_file.filename})
    *s = text(empty);
  return m;
}

}  // namespace

Ros2Publisher::Ros2Publisher(Participant& p, Graph& graph, const std::string& prefix,
                             lrd::node::PublishSettings settings)
    : TopicPublisher(std::move(settings)),
      pose_(p, dds_topic_name(prefix + "/pose"), &geometry_msgs_msg_dds__PoseStamped__desc, latched_qos(10)),
      tf_(p, dds_topic_name("/tf"), &tf2_msgs_msg_dds__TFMessage__desc, default_qos(100)),
      tf_static_(p, dds_topic_name("/tf_static"), &tf2_msgs_msg_dds__TFMessage__desc, latched_qos(1)),
      path_(p, dds_topic_name(prefix + "/path"), &nav_msgs_msg_dds__Path__desc, latched_qos(1)),
      map_points_(p, dds_topic_name(prefix + "/map_points"), &sensor_msgs_msg_dds__PointCloud2__desc,
                  latched_qos(1)),
      dense_map_(p, dds_topic_name(prefix + "/dense_map"), &sensor_msgs_msg_dds__PointCloud2__desc,
                 latched_qos(1)),
      keyframes_(p, dds_topic_name(prefix + "/keyframes"), &visualization_msgs_msg_dds__MarkerArray__desc,
                 latched_qos(1)),
      occupancy_(p, dds_topic_name(prefix + "/occupancy"), &nav_msgs_msg_dds__OccupancyGrid__desc,
                 latched_qos(1)),
      mask_(p, dds_topic_name(prefix + "/dynamic_mask"), &sensor_msgs_msg_dds__Image__desc, default_qos(2)),
      overlay_(p, dds_topic_name(prefix + "/overlay"), &sensor_msgs_msg_dds__Image__desc, default_qos(2)),
      state_(p, dds_topic_name(prefix + "/state"), &std_msgs_msg_dds__String__desc, latched_qos(1)) {
  for (const WriterBase* w :
       std::initializer_list<const WriterBase*>{&pose_, &tf_, &tf_static_, &path_, &map_points_, &dense_map_,
                                                &keyframes_, &occupancy_, &mask_, &overlay_, &state_})
    graph.add_writer(w->handle());
  start();
}

Ros2Publisher::~Ros2Publisher() {
  stop_occupancy();  // its thread calls the send_* below
}

void Ros2Publisher::warn(const std::string& what) {
  // The occupancy thread's only: at most one a period, so no throttle of its own.
  std::fprintf(stderr, "[WARN] lrdslam: %s\n", what.c_str());
}

void Ros2Publisher::send_static_transform(const std::string& parent, const std::string& child,
                                          const Eigen::Isometry3d& T) {
  geometry_msgs_msg_dds__TransformStamped_ t{};
  t.header = header(now_seconds(), parent);
  t.child_frame_id = text(child);
  t.transform = transform_message(T);
  tf2_msgs_msg_dds__TFMessage_ m{};
  set_sequence(m.transforms, &t, 1);
  tf_static_.write(m);
}

void Ros2Publisher::send_state(const std::string& state) {
  std_msgs_msg_dds__String_ m{text(state)};
  state_.write(m);
}

void Ros2Publisher::send_pose(double stamp, const Eigen::Isometry3d& T) {
  geometry_msgs_msg_dds__PoseStamped_ pose{};
  pose.header = header(stamp, settings().map_frame);
  pose.pose = pose_message(T);
  pose_.write(pose);

  geometry_msgs_msg_dds__TransformStamped_ t{};
  t.header = pose.header;
  t.child_frame_id = text(camera_frame());
  t.transform = transform_message(T);
  tf2_msgs_msg_dds__TFMessage_ m{};
  set_sequence(m.transforms, &t, 1);
  tf_.write(m);
}

void Ros2Publisher::send_path(double stamp, const lrd::io::Trajectory& path) {
  std::vector<geometry_msgs_msg_dds__PoseStamped_> poses(path.size());
  for (std::size_t i = 0; i < path.size(); ++i) {
    poses[i].header = header(path[i].timestamp, settings().map_frame);
    poses[i].pose = pose_message(path[i].pose);
  }
  nav_msgs_msg_dds__Path_ m{};
  m.header = header(path.empty() ? now_seconds() : stamp, settings().map_frame);
  set_sequence(m.poses, poses.data(), poses.size());
  path_.write(m);
}

void Ros2Publisher::send_cloud(Writer<sensor_msgs_msg_dds__PointCloud2_>& writer,
                               const lrd::node::PackedCloud& c) {
  std::vector<sensor_msgs_msg_dds__PointField_> fields(c.fields.size());
  for (std::size_t i = 0; i < c.fields.size(); ++i)
    fields[i] = {text(c.fields[i].name), c.fields[i].offset, lrd::node::kPointFieldFloat32, 1};
  sensor_msgs_msg_dds__PointCloud2_ m{};
  m.header = header(now_seconds(), settings().map_frame);
  m.height = 1;
  m.width = c.width;
  set_sequence(m.fields, fields.data(), fields.size());
  m.is_bigendian = false;
  m.point_step = c.point_step;
  m.row_step = c.point_step * c.width;
  set_sequence(m.data, const_cast<std::uint8_t*>(c.data.data()), c.data.size());
  m.is_dense = true;
  writer.write(m);
}

void Ros2Publisher::send_keyframes(const lrd::events::MapSnapshot& map, double now) {
  std::vector<geometry_msgs_msg_dds__Point_> points;
  for (const lrd::events::KeyframePose& k : map.keyframes)
    for (const Eigen::Vector3d& v : lrd::node::frustum_lines(k.T_wc)) points.push_back({v.x(), v.y(), v.z()});
  visualization_msgs_msg_dds__Marker_ marker = keyframe_marker(settings().map_frame, now, points);
  visualization_msgs_msg_dds__MarkerArray_ array{};
  set_sequence(array.markers, &marker, 1);
  keyframes_.write(array);
}

void Ros2Publisher::send_map(const lrd::events::MapSnapshot& map) {
  send_cloud(map_points_, lrd::node::pack_cloud(map.points));
  send_keyframes(map, now_seconds());
}

void Ros2Publisher::send_dense_map(const lrd::dense::PointCloud& cloud) {
  send_cloud(dense_map_, lrd::node::pack_cloud(cloud));
}

void Ros2Publisher::send_occupancy(const lrd::occupancy::Occupancy& occupancy) {
  const lrd::occupancy::Grid2d& grid = occupancy.grid;
  nav_msgs_msg_dds__OccupancyGrid_ m{};
  const double now = now_seconds();
  m.header = header(now, settings().map_frame);
  m.info.map_load_time = m.header.stamp;
  m.info.resolution = static_cast<float>(grid.resolution);
  m.info.width = static_cast<std::uint32_t>(grid.width);
  m.info.height = static_cast<std::uint32_t>(grid.height);
  m.info.origin = pose_message(lrd::node::grid_origin(grid));
  set_sequence(m.data, const_cast<std::int8_t*>(grid.cells.data()), grid.cells.size());
  occupancy_.write(m);
}

void Ros2Publisher::send_mask(double stamp, const cv::Mat& mask) {
  const lrd::bag::ImagePixels pixels = lrd::bag::mono_pixels(mask);
  mask_.write(image_message(pixels, stamp, camera_frame()));
}

void Ros2Publisher::send_overlay(double stamp, const cv::Mat& bgr) {
  const lrd::bag::ImagePixels pixels = lrd::bag::colour_pixels(bgr);
  overlay_.write(image_message(pixels, stamp, camera_frame()));
}

}  // namespace lrd_ros2
