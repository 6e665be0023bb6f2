#include "lrd/rosbag2/rosbag2_sequence.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>

#include "lrd/bag/camera_info.h"
#include "lrd/bag/frame_pairing.h"
#include "lrd/bag/image_pixels.h"
#include "lrd/bag/stamp.h"
#include "lrd/bag/tf_ground_truth.h"
#include "lrd/rosbag2/messages.h"
#include "lrd/util/error.h"

namespace lrd::rosbag2 {

namespace fs = std::filesystem;

namespace {

double seconds(const msg::Time& t) {
  return bag::to_seconds({t.sec, t.nanosec});
}

bag::ImageView view_of(const msg::Image& m) {
  return {m.width, m.height, m.encoding, m.is_bigendian, m.step, m.data.data(), m.data.size()};
}

Eigen::Isometry3d isometry_of(const msg::Transform& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const msg::Quaternion& q = t.rotation;
  T.linear() = Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  return T;
}

}  // namespace

template <typename Decode>
auto Rosbag2Sequence::decode(const std::string& topic, const MessageRef& ref, Decode decode) const {
  const std::vector<std::uint8_t> bytes = storage_->read(ref);
  try {
    return decode(bytes.data(), bytes.size());
  } catch (const lrd::Error& e) {
    throw file_error(storage_->file(),
                     fmt::format("topic {}: the message recorded at {:.9f} s cannot be read: {}", topic,
                                 static_cast<double>(ref.log_time_ns) * 1e-9, e.what()));
  }
}

std::shared_ptr<Rosbag2Sequence> Rosbag2Sequence::open(const fs::path& bag, const bag::BagTopics& topics) {
  std::shared_ptr<Rosbag2Sequence> seq(new Rosbag2Sequence());
  seq->path_ = bag;
  seq->topics_ = topics;
  seq->storage_ = open_storage(bag);
  seq->read_frames();
  seq->read_camera();
  if (!topics.gt_child.empty()) seq->read_ground_truth();
  // An encoding it cannot read, or an image of another size than camera_info, fails now, before
  // any tracking.
  (void)seq->load_rgbd(0, 1.0);
  return seq;
}

void Rosbag2Sequence::read_frames() {
  const fs::path& file = storage_->file();
  bag::require_topic(file, topics_.rgb, storage_->topics(), msg::kImageType);
  bag::require_topic(file, topics_.depth, storage_->topics(), msg::kImageType);
  const std::vector<MessageRef> rgb = storage_->messages(topics_.rgb),
                                depth = storage_->messages(topics_.depth);
  // Each image's header stamp, read in storage order (an MCAP chunk is decompressed once).
  struct Pending {
    MessageRef ref;
    const std::string* topic;
    double* stamp;
  };
  std::vector<double> rgb_stamps(rgb.size()), depth_stamps(depth.size());
  std::vector<Pending> pending;
  for (std::size_t k = 0; k < rgb.size(); ++k) pending.push_back({rgb[k], &topics_.rgb, &rgb_stamps[k]});
  for (std::size_t k = 0; k < depth.size(); ++k)
    pending.push_back({depth[k], &topics_.depth, &depth_stamps[k]});
  std::sort(pending.begin(), pending.end(), [](const Pending& x, const Pending& y) { return x.ref < y.ref; });
  for (const Pending& p : pending) *p.stamp = seconds(decode(*p.topic, p.ref, msg::decode_header).stamp);
  const bag::FramePairs pairs = bag::pair_frames(file, topics_, rgb_stamps, depth_stamps);
  entries_ = pairs.entries;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    rgb_.push_back(rgb[pairs.rgb[i]]);
    depth_.push_back(depth[pairs.depth[i]]);
  }
}

void Rosbag2Sequence::read_camera() {
  const auto type = storage_->topics().find(topics_.camera_info);
  if (topics_.camera_info.empty() || type == storage_->topics().end()) return;
  const fs::path& file = storage_->file();
  if (type->second != msg::kCameraInfoType)
    throw bag::wrong_type(file, topics_.camera_info, type->second, msg::kCameraInfoType);
  const std::vector<MessageRef> refs = storage_->messages(topics_.camera_info);
  if (refs.empty()) return;
  const msg::CameraInfo info = decode(topics_.camera_info, refs.front(), msg::decode_camera_info);
  bag::CameraCalibration c;
  c.width = info.width;
  c.height = info.height;
  c.distortion_model = info.distortion_model;
  c.d = info.d;
  c.k = info.k;
  try {
    camera_ = bag::camera_from_calibration(c);
  } catch (const lrd::Error& e) {
    throw file_error(file, "topic " + topics_.camera_info + ": " + e.what());
  }
  camera_->origin = fmt::format("camera_info {} in {}", topics_.camera_info, file.string());
}

void Rosbag2Sequence::read_ground_truth() {
  bag::TfGroundTruth tf;
  for (const std::string topic : {"/tf", "/tf_static"}) {
    const auto type = storage_->topics().find(topic);
    if (type == storage_->topics().end()) continue;
    if (type->second != msg::kTfMessageType)
      throw bag::wrong_type(storage_->file(), topic, type->second, msg::kTfMessageType);
    for (const MessageRef& ref : storage_->messages(topic))
      for (const msg::TransformStamped& t : decode(topic, ref, msg::decode_tf_message).transforms)
        tf.add(t.header.frame_id, t.child_frame_id, {t.header.stamp.sec, t.header.stamp.nanosec},
               isometry_of(t.transform), topic == "/tf_static");
  }
  ground_truth_ = tf.trajectory(storage_->file(), topics_);
}

io::RgbdFrame Rosbag2Sequence::load_rgbd(std::size_t i,
                                         double /*depth_factor: depth carries its unit*/) const {
  io::RgbdFrame f;
  f.index = i;
  f.timestamp = entries_.at(i).timestamp;
  const auto read = [this](const std::string& topic, const MessageRef& ref, auto convert) {
    const msg::Image image = decode(topic, ref, msg::decode_image);
    try {
      return convert(view_of(image));
    } catch (const lrd::Error& e) {
      throw file_error(storage_->file(),
                       fmt::format("topic {} at {:.6f}: {}", topic, seconds(image.header.stamp), e.what()));
    }
  };
  f.rgb = read(topics_.rgb, rgb_[i], bag::colour_from_image);
  f.depth = read(topics_.depth, depth_[i], bag::depth_from_image);
  bag::check_frame_size(storage_->file(), topics_, f);
  bag::check_camera_size(storage_->file(), topics_, f, camera_);
  return f;
}

std::string Rosbag2Sequence::describe(std::size_t i) const {
  return fmt::format("{}: {} at {:.6f}", storage_->file().string(), topics_.rgb, entries_.at(i).timestamp);
}

std::string Rosbag2Sequence::ground_truth_origin() const {
  return fmt::format("{} /tf {} -> {}", storage_->file().string(), topics_.gt_parent, topics_.gt_child);
}

}  // namespace lrd::rosbag2
