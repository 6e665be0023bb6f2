#include "lrd/rosbag2/rosbag2_writer.h"

#include <fmt/format.h>

#include <map>
#include <memory>
#include <optional>

#include "lrd/bag/camera_info.h"
#include "lrd/bag/image_pixels.h"
#include "lrd/bag/stamp.h"
#include "lrd/rosbag2/mcap_writer.h"
#include "lrd/rosbag2/messages.h"
#include "lrd/rosbag2/sqlite_bag.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::rosbag2 {

namespace fs = std::filesystem;

namespace {

// Where the messages go: an MCAP file or a sqlite3 file and its metadata.yaml.
class MessageSink {
 public:
  virtual ~MessageSink() = default;
  virtual int add_topic(const std::string& name, const std::string& type) = 0;
  virtual void write(int topic, std::int64_t time_ns, const std::vector<std::uint8_t>& data) = 0;
  virtual void close() = 0;
};

class McapSink final : public MessageSink {
 public:
  McapSink(const fs::path& file, Compression compression) : writer_(file, {compression, 4u << 20, "ros2"}) {}
  int add_topic(const std::string& name, const std::string& type) override {
    auto schema = schemas_.find(type);
    if (schema == schemas_.end())
      schema = schemas_.emplace(type, writer_.add_schema(type, "ros2msg", msg::definition(type))).first;
    return writer_.add_channel(schema->second, name, "cdr");
  }
  void write(int topic, std::int64_t time_ns, const std::vector<std::uint8_t>& data) override {
    writer_.write(static_cast<std::uint16_t>(topic), static_cast<std::uint64_t>(time_ns), data);
  }
  void close() override { writer_.close(); }

 private:
  McapWriter writer_;
  std::map<std::string, std::uint16_t> schemas_;
};

class Sqlite3Sink final : public MessageSink {
 public:
  explicit Sqlite3Sink(const fs::path& file) : file_(file), writer_(file) {}
  int add_topic(const std::string& name, const std::string& type) override {
    topics_.push_back({{name, type, "cdr"}, 0});
    return static_cast<int>(writer_.add_topic(topics_.back().info));
  }
  void write(int topic, std::int64_t time_ns, const std::vector<std::uint8_t>& data) override {
    writer_.write(topic, time_ns, data);
    ++topics_.at(static_cast<std::size_t>(topic - 1)).count;
    start_ = std::min(start_.value_or(time_ns), time_ns);
    end_ = std::max(end_.value_or(time_ns), time_ns);
  }
  void close() override {
    writer_.close();
    util::write_file_bytes(file_.parent_path() / "metadata.yaml", metadata());
  }

 private:
  // rosbag2's metadata.yaml (version 5, as humble writes it).
  std::string metadata() const {
    std::size_t messages = 0;
    for (const Topic& t : topics_) messages += t.count;
    const std::int64_t start = start_.value_or(0), duration = end_.value_or(0) - start;
    const std::string name = file_.filename().string();
    std::string y = "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n";
    y += fmt::format("  duration:\n    nanoseconds: {}\n  starting_time:\n    nanoseconds_since_epoch: {}\n",
                     duration, start);
    y += fmt::format("  message_count: {}\n  topics_with_message_count:\n", messages);
    for (const Topic& t : topics_)
      y += fmt::format(
          "    - topic_metadata:\n        name: {}\n        type: {}\n        serialization_format: cdr\n"
          "        offered_qos_profiles: \"\"\n      message_count: {}\n",
          t.info.name, t.info.type, t.count);
    y += fmt::format(
        "  compression_format: \"\"\n  compression_mode: \"\"\n  relative_file_paths:\n    - {}\n", name);
    y += fmt::format(
        "  files:\n    - path: {}\n      starting_time:\n        nanoseconds_since_epoch: {}\n"
        "      duration:\n        nanoseconds: {}\n      message_count: {}\n",
        name, start, duration, messages);
    return y;
  }

  struct Topic {
    TopicInfo info;
    std::size_t count;
  };
  fs::path file_;
  Sqlite3Writer writer_;
  std::vector<Topic> topics_;
  std::optional<std::int64_t> start_, end_;
};

msg::Header header(double seconds, const std::string& frame_id) {
  const bag::Stamp s = bag::to_stamp(seconds);
  return {{static_cast<std::int32_t>(s.sec), s.nanosec}, frame_id};
}

msg::Image image_message(const bag::ImagePixels& p, const msg::Header& h) {
  return {h, p.height, p.width, p.encoding, 0, p.step, p.data};
}

msg::CameraInfo camera_info_message(const bag::CameraCalibration& c, const msg::Header& h) {
  msg::CameraInfo m;
  m.header = h;
  m.height = c.height;
  m.width = c.width;
  m.distortion_model = c.distortion_model;
  m.d = c.d;
  m.k = c.k;
  m.r = c.r;
  m.p = c.p;
  return m;
}

msg::TFMessage tf_message(const io::StampedPose& p, const bag::BagLayout& layout) {
  const Eigen::Quaterniond q(p.pose.linear());
  const Eigen::Vector3d t = p.pose.translation();
  msg::TransformStamped s;
  s.header = header(p.timestamp, layout.topics.gt_parent);
  s.child_frame_id = layout.topics.gt_child;
  s.transform = {{t.x(), t.y(), t.z()}, {q.x(), q.y(), q.z(), q.w()}};
  return {{s}};
}

std::int64_t nanoseconds(const msg::Header& h) {
  return bag::to_nanoseconds({h.stamp.sec, h.stamp.nanosec});
}

void write_messages(const io::FrameSource& source, const camera::PinholeCamera& camera,
                    const bag::BagLayout& layout, MessageSink& sink) {
  const int rgb = sink.add_topic(layout.topics.rgb, msg::kImageType);
  const int rgb_info = sink.add_topic(layout.topics.camera_info, msg::kCameraInfoType);
  const int depth = sink.add_topic(layout.topics.depth, msg::kImageType);
  const int depth_info = sink.add_topic(layout.depth_camera_info, msg::kCameraInfoType);
  const std::optional<io::Trajectory> gt = source.ground_truth();
  const int tf = gt ? sink.add_topic("/tf", msg::kTfMessageType) : 0;
  const bag::CameraCalibration calibration = bag::calibration_of(camera);
  for (std::size_t i = 0; i < source.size(); ++i) {
    const io::FrameEntry& e = source.entry(i);
    const io::RgbdFrame f = source.load_rgbd(i, camera.depth_map_factor);
    const msg::Header h_rgb = header(e.timestamp, layout.rgb_frame);
    const msg::Header h_depth = header(e.depth_timestamp, layout.depth_frame);
    sink.write(rgb, nanoseconds(h_rgb), msg::encode(image_message(bag::colour_pixels(f.rgb), h_rgb)));
    sink.write(rgb_info, nanoseconds(h_rgb), msg::encode(camera_info_message(calibration, h_rgb)));
    sink.write(depth, nanoseconds(h_depth), msg::encode(image_message(bag::depth_pixels(f.depth), h_depth)));
    sink.write(depth_info, nanoseconds(h_depth), msg::encode(camera_info_message(calibration, h_depth)));
  }
  if (gt)
    for (const io::StampedPose& p : *gt) {
      const msg::TFMessage m = tf_message(p, layout);
      sink.write(tf, nanoseconds(m.transforms.front().header), msg::encode(m));
    }
}

}  // namespace

bool is_rosbag2_path(const fs::path& bag) {
  return bag.extension() == ".mcap" || bag.extension() == ".db3";
}

void write_rosbag2(const io::FrameSource& source, const camera::PinholeCamera& camera, const fs::path& bag,
                   const bag::BagLayout& layout, Compression compression) {
  std::unique_ptr<MessageSink> sink;
  if (bag.extension() == ".mcap")
    sink = std::make_unique<McapSink>(bag, compression);
  else if (bag.extension() == ".db3") {
    // A .db3 and its metadata.yaml are a rosbag2 bag folder: made as `ros2 bag record` makes it.
    std::error_code ec;
    if (bag.has_parent_path()) fs::create_directories(bag.parent_path(), ec);
    sink = std::make_unique<Sqlite3Sink>(bag);
  } else
    throw file_error(bag, "a ROS 2 bag is written as FILE.mcap or FILE.db3");
  write_messages(source, camera, layout, *sink);
  sink->close();
}

}  // namespace lrd::rosbag2
