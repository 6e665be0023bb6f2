#pragma once
// An RGB-D sequence read straight from a rosbag (rosbag_storage: no roscore), in the layout of the
// TUM RGB-D bags: colour and depth images on two topics, a camera_info, and the motion-capture
// ground truth on /tf. Colour and depth pair by associate.py's rule, as the folder reader does, so
// the same frames give the same run from a bag and from a folder. Everything but the message
// format is shared with the ROS 2 bag reader (lrd/bag/).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lrd/bag/bag_layout.h"
#include "lrd/io/frame_source.h"

namespace lrd_ros {

// The topics and ground-truth frames, and --gt-from-tf's parser, shared with the ROS 2 reader.
using BagTopics = lrd::bag::BagTopics;
using lrd::bag::parse_tf_pair;

class BagSequence final : public lrd::io::FrameSource {
 public:
  // Reads the bag's index and every image header (the pixels are read again when a frame is
  // loaded). Throws lrd::Error "BAG: problem" naming the topic where there is one: a missing or
  // unreadable (truncated, unindexed) bag, a missing topic or one of another message type, an
  // empty topic, a colour or depth encoding it cannot read, duplicate stamps, no colour image with
  // a depth image within max_dt, a /tf without the ground-truth frames.
  [[nodiscard]] static std::shared_ptr<BagSequence> open(const std::filesystem::path& bag,
                                                         const BagTopics& topics = {});
  ~BagSequence() override;
  BagSequence(const BagSequence&) = delete;
  BagSequence& operator=(const BagSequence&) = delete;

  [[nodiscard]] std::size_t size() const override { return entries_.size(); }
  [[nodiscard]] const lrd::io::FrameEntry& entry(std::size_t i) const override { return entries_.at(i); }
  [[nodiscard]] lrd::io::RgbdFrame load_rgbd(std::size_t i, double depth_factor) const override;
  [[nodiscard]] std::string describe(std::size_t i) const override;
  [[nodiscard]] std::filesystem::path path() const override { return file_; }
  [[nodiscard]] std::optional<std::filesystem::path> folder() const override { return std::nullopt; }
  [[nodiscard]] std::optional<lrd::io::Trajectory> ground_truth() const override { return ground_truth_; }
  [[nodiscard]] std::string ground_truth_origin() const override;
  [[nodiscard]] std::optional<lrd::io::SourceCamera> camera() const override { return camera_; }

  [[nodiscard]] const BagTopics& topics() const { return topics_; }

 private:
  struct Messages;  // the open bag and where each frame's two messages are (rosbag types)
  BagSequence();

  std::filesystem::path file_;
  BagTopics topics_;
  std::unique_ptr<Messages> messages_;
  std::vector<lrd::io::FrameEntry> entries_;
  std::optional<lrd::io::SourceCamera> camera_;
  std::optional<lrd::io::Trajectory> ground_truth_;
};

}  // namespace lrd_ros
