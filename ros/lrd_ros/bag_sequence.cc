#include "lrd_ros/bag_sequence.h"

#include <fmt/format.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <spdlog/spdlog.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <set>

#include "lrd/io/tum_sequence.h"
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

std::string without_slash(const std::string& frame) {
  return !frame.empty() && frame.front() == '/' ? frame.substr(1) : frame;
}

// Every topic of the bag with its message type, for "the bag has ..." in errors.
std::map<std::string, std::string> topic_types(const rosbag::Bag& bag) {
  rosbag::View all(bag);
  std::map<std::string, std::string> types;
  for (const rosbag::ConnectionInfo* c : all.getConnections()) types[c->topic] = c->datatype;
  return types;
}

std::string list_topics(const std::map<std::string, std::string>& types) {
  if (types.empty()) return "the bag has no topics";
  std::string s = "the bag has";
  for (const auto& [topic, type] : types) s += fmt::format(" {} ({})", topic, type);
  return s;
}

// The message instantiated as T, or an error naming the topic and both types.
template <typename T>
boost::shared_ptr<T> instantiate(const rosbag::MessageInstance& m, const fs::path& file,
                                 const char* expected) {
  boost::shared_ptr<T> message;
  try {
    message = m.instantiate<T>();
  } catch (const std::exception& e) {
    throw file_error(file, fmt::format("topic {}: message at {} cannot be read: {}", m.getTopic(),
                                       to_seconds(m.getTime()), e.what()));
  }
  if (!message)
    throw file_error(
        file, fmt::format("topic {} carries {}, expected {}", m.getTopic(), m.getDataType(), expected));
  return message;
}

struct StampedMessages {
  std::vector<rosbag::MessageInstance> messages;  // in stamp order
  std::vector<double> stamps;
};

// The image messages of a topic in stamp order (a recorder stores them in arrival order).
StampedMessages image_messages(const rosbag::Bag& bag, const fs::path& file, const std::string& topic,
                               const std::map<std::string, std::string>& types) {
  if (types.count(topic) == 0) throw file_error(file, "topic " + topic + " not found; " + list_topics(types));
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  std::vector<rosbag::MessageInstance> arrived;
  std::vector<double> stamps;
  for (const rosbag::MessageInstance& m : view) {
    const auto image = instantiate<sensor_msgs::Image>(m, file, "sensor_msgs/Image");
    arrived.push_back(m);
    stamps.push_back(to_seconds(image->header.stamp));
  }
  if (arrived.empty()) throw file_error(file, "topic " + topic + " has no messages");
  std::vector<std::size_t> order(arrived.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return stamps[a] < stamps[b]; });
  StampedMessages out;
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (k > 0 && stamps[order[k]] == stamps[order[k - 1]])
      throw file_error(file, fmt::format("topic {}: two messages stamped {:.9f}", topic, stamps[order[k]]));
    out.messages.push_back(arrived[order[k]]);
    out.stamps.push_back(stamps[order[k]]);
  }
  return out;
}

std::optional<lrd::io::SourceCamera> read_camera(const rosbag::Bag& bag, const fs::path& file,
                                                 const std::string& topic,
                                                 const std::map<std::string, std::string>& types) {
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

// CHILD's pose in PARENT at the stamp of every /tf transform on the chain above CHILD (the motion
// capture's rate; static links between, e.g. the camera's optical frame, are followed).
lrd::io::Trajectory read_ground_truth(const rosbag::Bag& bag, const fs::path& file, const BagTopics& t) {
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/tf", "/tf_static"}));
  if (view.size() == 0) throw file_error(file, "--gt-from-tf: the bag has no /tf messages");
  const std::string parent = without_slash(t.gt_parent), child = without_slash(t.gt_child);
  // The cache must hold the whole bag by header stamps, which need not follow the record times
  // (re-recorded bags, simulated time): ten years.
  tf2::BufferCore buffer(ros::Duration(3.2e8));
  std::map<std::string, std::string> parent_of;
  std::map<std::string, std::vector<ros::Time>> dynamic_stamps;  // child frame -> stamps on /tf
  for (const rosbag::MessageInstance& m : view) {
    const auto message = instantiate<tf2_msgs::TFMessage>(m, file, "tf2_msgs/TFMessage");
    const bool is_static = m.getTopic() == "/tf_static";
    for (geometry_msgs::TransformStamped transform : message->transforms) {
      transform.header.frame_id = without_slash(transform.header.frame_id);
      transform.child_frame_id = without_slash(transform.child_frame_id);
      parent_of[transform.child_frame_id] = transform.header.frame_id;
      buffer.setTransform(transform, "bag", is_static);
      if (!is_static) dynamic_stamps[transform.child_frame_id].push_back(transform.header.stamp);
    }
  }
  std::vector<ros::Time> stamps;
  std::set<std::string> chain;
  for (std::string f = child; !f.empty() && f != parent && chain.insert(f).second;) {
    const auto d = dynamic_stamps.find(f);
    if (d != dynamic_stamps.end()) stamps.insert(stamps.end(), d->second.begin(), d->second.end());
    const auto up = parent_of.find(f);
    f = up == parent_of.end() ? std::string() : up->second;
  }
  std::set<std::string> frames;
  for (const auto& [c, p] : parent_of) frames.insert({c, p});
  std::sort(stamps.begin(), stamps.end());
  stamps.erase(std::unique(stamps.begin(), stamps.end()), stamps.end());
  lrd::io::Trajectory gt;
  for (const ros::Time& stamp : stamps) {
    try {
      const geometry_msgs::TransformStamped x = buffer.lookupTransform(parent, child, stamp);
      gt.push_back({to_seconds(stamp), from_message(x.transform)});
    } catch (const tf2::TransformException&) {
      // Outside the span of another transform of the chain: no sample there.
    }
  }
  if (gt.empty()) {
    std::string known;
    for (const std::string& f : frames) known += " " + f;
    throw file_error(file, fmt::format("--gt-from-tf {}:{}: no transform from {} to {} on /tf (frames:{})",
                                       t.gt_parent, t.gt_child, t.gt_parent, t.gt_child, known));
  }
  return gt;
}

}  // namespace

std::pair<std::string, std::string> parse_tf_pair(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size() ||
      text.find(':', colon + 1) != std::string::npos)
    throw lrd::Error("--gt-from-tf expects PARENT:CHILD (e.g. /world:/kinect), got '" + text + "'");
  return {text.substr(0, colon), text.substr(colon + 1)};
}

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
    StampedMessages rgb = image_messages(m.bag, file, topics.rgb, types);
    StampedMessages depth = image_messages(m.bag, file, topics.depth, types);
    const auto pairs = lrd::io::associate_timestamps(rgb.stamps, depth.stamps, topics.max_dt);
    if (pairs.empty())
      throw file_error(file, fmt::format("none of the {} messages on {} has a depth image on {} within {} s",
                                         rgb.stamps.size(), topics.rgb, topics.depth, topics.max_dt));
    for (const auto& [i, j] : pairs) {
      // Named like the folder layout's files, so outputs named after frames match.
      seq->entries_.push_back({rgb.stamps[i], fs::path("rgb") / fmt::format("{:.6f}.png", rgb.stamps[i]),
                               depth.stamps[j],
                               fs::path("depth") / fmt::format("{:.6f}.png", depth.stamps[j])});
      m.rgb.push_back(rgb.messages[i]);
      m.depth.push_back(depth.messages[j]);
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
  if (f.rgb.size() != f.depth.size())
    throw file_error(
        file_, fmt::format("{} at {:.6f} is {}x{} but its depth on {} is {}x{}", topics_.rgb, f.timestamp,
                           f.rgb.cols, f.rgb.rows, topics_.depth, f.depth.cols, f.depth.rows));
  return f;
}

std::string BagSequence::describe(std::size_t i) const {
  return fmt::format("{}: {} at {:.6f}", file_.string(), topics_.rgb, entries_.at(i).timestamp);
}

std::string BagSequence::ground_truth_origin() const {
  return fmt::format("{} /tf {} -> {}", file_.string(), topics_.gt_parent, topics_.gt_child);
}

}  // namespace lrd_ros
