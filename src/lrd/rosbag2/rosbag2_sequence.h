#pragma once
// An RGB-D sequence read from a ROS 2 bag (rosbag2's sqlite3 or MCAP storage, our own reader: no
// ROS installed) in the layout of the TUM RGB-D bags: colour and depth images on two topics, a
// camera_info, and the motion-capture ground truth on /tf. Everything but the message format is
// the ROS 1 bag reader's (lrd/bag/), so the same frames give the same run from either bag and
// from a folder.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lrd/bag/bag_layout.h"
#include "lrd/io/frame_source.h"
#include "lrd/rosbag2/bag_storage.h"

namespace lrd::rosbag2 {

class Rosbag2Sequence final : public io::FrameSource {
 public:
  // Reads the bag's records and every image header (the pixels are read again when a frame is
  // loaded). Throws lrd::Error "BAG: problem" naming the topic where there is one: a missing,
  // truncated or corrupted bag, a missing topic or one of another type, a message shorter than
  // its fields, an empty topic, an encoding it cannot read, duplicate stamps, no colour image with
  // a depth image within max_dt, an image of another size than camera_info, a /tf without the
  // ground-truth frames.
  [[nodiscard]] static std::shared_ptr<Rosbag2Sequence> open(const std::filesystem::path& bag,
                                                             const bag::BagTopics& topics = {});

  [[nodiscard]] std::size_t size() const override { return entries_.size(); }
  [[nodiscard]] const io::FrameEntry& entry(std::size_t i) const override { return entries_.at(i); }
  [[nodiscard]] io::RgbdFrame load_rgbd(std::size_t i, double depth_factor) const override;
  [[nodiscard]] std::string describe(std::size_t i) const override;
  [[nodiscard]] std::filesystem::path path() const override { return path_; }
  [[nodiscard]] std::optional<std::filesystem::path> folder() const override { return std::nullopt; }
  [[nodiscard]] std::optional<io::Trajectory> ground_truth() const override { return ground_truth_; }
  [[nodiscard]] std::string ground_truth_origin() const override;
  [[nodiscard]] std::optional<io::SourceCamera> camera() const override { return camera_; }

 private:
  Rosbag2Sequence() = default;
  void read_frames();
  void read_camera();
  void read_ground_truth();
  // Decodes one message; lrd::Error naming the file and topic for a malformed one.
  template <typename Decode>
  auto decode(const std::string& topic, const MessageRef& ref, Decode decode) const;

  std::filesystem::path path_;
  bag::BagTopics topics_;
  std::unique_ptr<BagStorage> storage_;
  std::vector<io::FrameEntry> entries_;
  std::vector<MessageRef> rgb_, depth_;  // frame i's messages
  std::optional<io::SourceCamera> camera_;
  std::optional<io::Trajectory> ground_truth_;
};

}  // namespace lrd::rosbag2
