#pragma once
// The part of reading an RGB-D bag that does not depend on its format (ROS 1 .bag, rosbag2 sqlite3
// or MCAP): the topic checks and their error texts, colour and depth in stamp order paired by
// associate.py's rule as the folder reader pairs them, and each frame named like the folder
// layout's files, so the same frames give the same run from a bag and from a folder.
#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "lrd/bag/bag_layout.h"
#include "lrd/io/frame_source.h"
#include "lrd/util/error.h"

namespace lrd::bag {

// Every topic of a bag with its message type.
using TopicTypes = std::map<std::string, std::string>;

// " /a (type) /b (type)" for "the bag has ..." in errors.
[[nodiscard]] std::string list_topics(const TopicTypes& types);
// Throws lrd::Error "FILE: topic T not found; the bag has ..." or "topic T carries X, expected Y".
void require_topic(const std::filesystem::path& file, const std::string& topic, const TopicTypes& types,
                   const std::string& expected_type);
[[nodiscard]] lrd::Error wrong_type(const std::filesystem::path& file, const std::string& topic,
                                    const std::string& actual, const std::string& expected);

// Frame i's colour and depth messages as indices into their topic's messages in bag order.
struct FramePairs {
  std::vector<io::FrameEntry> entries;
  std::vector<std::size_t> rgb, depth;
};

// The colour and depth messages' header stamps (s) in bag order -> the frames. Throws lrd::Error
// naming the file and topic for an empty topic, two messages with one stamp, or no colour image
// with a depth image within topics.max_dt.
[[nodiscard]] FramePairs pair_frames(const std::filesystem::path& file, const BagTopics& topics,
                                     const std::vector<double>& rgb_stamps,
                                     const std::vector<double>& depth_stamps);

// A loaded frame's colour against its depth: throws lrd::Error naming the file and topics when
// their sizes differ.
void check_frame_size(const std::filesystem::path& file, const BagTopics& topics, const io::RgbdFrame& frame);
// A loaded frame against the bag's camera_info, likewise.
void check_camera_size(const std::filesystem::path& file, const BagTopics& topics, const io::RgbdFrame& frame,
                       const std::optional<io::SourceCamera>& camera);

}  // namespace lrd::bag
