#include "lrd_ros/bag_sequence.h"

#include <fmt/format.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <spdlog/spdlog.h>
#include <tf2_msgs/TFMessage.h>

#include <boost/make_shared.hpp>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "lrd/bag/frame_pairing.h"
#include "lrd/bag/ros1_bag_structure.h"
#include "lrd/bag/ros1_message_lengths.h"
#include "lrd/bag/tf_ground_truth.h"
#include "lrd/util/error.h"
#include "lrd_ros/image_messages.h"
#include "lrd_ros/pose_messages.h"

namespace lrd_ros {

namespace fs = std::filesystem;
using lrd::file_error;

struct BagSequence::Messages {
  rosbag::Bag bag;
  // Frame i's colour and depth messages (valid while the bag is open).
  std::vector<rosbag::MessageInstance> rgb, depth;
};

namespace {

// Every topic of the bag with its message type, for "the bag has ..." in errors.
lrd::bag::TopicTypes topic_types(const rosbag::Bag& bag) {
  rosbag::View all(bag);
  lrd::bag::TopicTypes types;
  for (const rosbag::ConnectionInfo* c : all.getConnections()) types[c->topic] = c->datatype;
  return types;
}

// The message instantiated as T, or an error naming the topic and both types.
template <typename T>
boost::shared_ptr<T> instantiate(const rosbag::MessageInstance& m, const fs::path& file,
                                 const char* expected) {
  // isType: rosbag's own test in instantiate (the MD5 sum of the definition).
  if (!m.isType<T>()) throw lrd::bag::wrong_type(file, m.getTopic(), m.getDataType(), expected);
  auto message = boost::make_shared<T>();
  try {
    // ROS's deserializer sizes strings and arrays from their length prefixes before reading them:
    // the message's bytes are copied out once, their prefixes checked (lrd/bag/ros1_message_lengths.h),
    // and the message deserialized from that copy.
    if (m.size() > lrd::bag::kMaxRos1ChunkBytes)
      throw std::runtime_error(fmt::format("it states {} bytes, more than a chunk holds", m.size()));
    std::vector<std::uint8_t> raw(m.size());
    ros::serialization::OStream out(raw.data(), static_cast<std::uint32_t>(raw.size()));
    m.write(out);
    const std::string problem =
        lrd::bag::ros1_length_problem(ros::message_traits::datatype<T>(), raw.data(), raw.size());
    if (!problem.empty()) throw std::runtime_error(problem);
    ros::serialization::IStream in(raw.data(), static_cast<std::uint32_t>(raw.size()));
    ros::serialization::deserialize(in, *message);
  } catch (const std::exception& e) {
    throw file_error(file, fmt::format("topic {}: message at {} cannot be read: {}", m.getTopic(),
                                       to_seconds(m.getTime()), e.what()));
  }
  return message;
}

// The image messages of a topic in bag order, with their header stamps.
struct TopicImages {
  std::vector<rosbag::MessageInstance> messages;
  std::vector<double> stamps;
};

TopicImages image_messages(const rosbag::Bag& bag, const fs::path& file, const std::string& topic,
                           const lrd::bag::TopicTypes& types) {
  if (types.count(topic) == 0)
    throw file_error(file, "topic " + topic + " not found; " + lrd::bag::list_topics(types));
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  TopicImages out;
  for (const rosbag::MessageInstance& m : view) {
    const auto image = instantiate<sensor_msgs::Image>(m, file, "sensor_msgs/Image");
    out.messages.push_back(m);
    out.stamps.push_back(to_seconds(image->header.stamp));
  }
  return out;
}

std::optional<lrd::io::SourceCamera> read_camera(const rosbag::Bag& bag, const fs::path& file,
                                                 const std::string& topic,
                                                 const lrd::bag::TopicTypes& types) {
  if (topic.empty() || types.count(topic) == 0) return std::nullopt;
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  for (const rosbag::MessageInstance& m : view) {
    const auto info = instantiate<sensor_msgs::CameraInfo>(m, file, "sensor_msgs/CameraInfo");
    try {
      lrd::io::SourceCamera c = camera_from_message(*info);
      c.origin = fmt::format("camera_info {} in {}", topic, file.string());
      return c;
    } catch (const lrd::Error& e) {
      throw file_error(file, "topic " + topic + ": " + e.what());
    }
  }
  return std::nullopt;
}

// The ground truth from /tf and /tf_static (lrd::bag::TfGroundTruth follows the chain).
lrd::io::Trajectory read_ground_truth(const rosbag::Bag& bag, const fs::path& file, const BagTopics& t) {
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/tf", "/tf_static"}));
  lrd::bag::TfGroundTruth tf;
  for (const rosbag::MessageInstance& m : view) {
    const auto message = instantiate<tf2_msgs::TFMessage>(m, file, "tf2_msgs/TFMessage");
    for (const geometry_msgs::TransformStamped& x : message->transforms)
      tf.add(x.header.frame_id, x.child_frame_id, {x.header.stamp.sec, x.header.stamp.nsec},
             from_message(x.transform), m.getTopic() == "/tf_static");
  }
  return tf.trajectory(file, t);
}

}  // namespace

BagSequence::BagSequence() : messages_(std::make_unique<Messages>()) {}
BagSequence::~BagSequence() = default;

std::shared_ptr<BagSequence> BagSequence::open(const fs::path& file, const BagTopics& topics) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw file_error(file, "bag file not found");
  if (!fs::is_regular_file(file, ec)) throw file_error(file, "not a bag file (not a regular file)");
  std::shared_ptr<BagSequence> seq(new BagSequence());
  seq->file_ = file;
  seq->topics_ = topics;
  Messages& m = *seq->messages_;
  lrd::bag::check_ros1_bag_structure(file);  // rosbag_storage trusts the lengths a bag states
  try {
    m.bag.open(file.string(), rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw file_error(file,
                     std::string("cannot read the bag (truncated or not a bag? `rosbag reindex` repairs "
                                 "an unindexed one): ") +
                         e.what());
  }
  try {
    const auto types = topic_types(m.bag);
    const TopicImages rgb = image_messages(m.bag, file, topics.rgb, types);
    const TopicImages depth = image_messages(m.bag, file, topics.depth, types);
    const lrd::bag::FramePairs pairs = lrd::bag::pair_frames(file, topics, rgb.stamps, depth.stamps);
    seq->entries_ = pairs.entries;
    for (std::size_t i = 0; i < pairs.entries.size(); ++i) {
      m.rgb.push_back(rgb.messages[pairs.rgb[i]]);
      m.depth.push_back(depth.messages[pairs.depth[i]]);
    }
    seq->camera_ = read_camera(m.bag, file, topics.camera_info, types);
    if (!topics.gt_child.empty()) seq->ground_truth_ = read_ground_truth(m.bag, file, topics);
    // An encoding it cannot read fails now, before any tracking.
    (void)seq->load_rgbd(0, 1.0);
  } catch (const rosbag::BagException& e) {
    throw file_error(file, std::string("cannot read the bag: ") + e.what());
  }
  return seq;
}

lrd::io::RgbdFrame BagSequence::load_rgbd(std::size_t i,
                                          double /*depth_factor: depth carries its unit*/) const {
  lrd::io::RgbdFrame f;
  f.index = i;
  f.timestamp = entries_.at(i).timestamp;
  const auto read = [this](const rosbag::MessageInstance& message, auto convert) {
    const auto image = instantiate<sensor_msgs::Image>(message, file_, "sensor_msgs/Image");
    try {
      return convert(*image);
    } catch (const lrd::Error& e) {
      throw file_error(file_, fmt::format("topic {} at {:.6f}: {}", message.getTopic(),
                                          to_seconds(image->header.stamp), e.what()));
    }
  };
  try {
    f.rgb = read(messages_->rgb[i], colour_from_message);
    f.depth = read(messages_->depth[i], depth_from_message);
  } catch (const rosbag::BagException& e) {
    throw file_error(file_, fmt::format("frame at {:.6f} cannot be read: {}", f.timestamp, e.what()));
  }
  lrd::bag::check_frame_size(file_, topics_, f);
  return f;
}

std::string BagSequence::describe(std::size_t i) const {
  return fmt::format("{}: {} at {:.6f}", file_.string(), topics_.rgb, entries_.at(i).timestamp);
}

std::string BagSequence::ground_truth_origin() const {
  return fmt::format("{} /tf {} -> {}", file_.string(), topics_.gt_parent, topics_.gt_child);
}

}  // namespace lrd_ros
