#include "lrd/bag/frame_pairing.h"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>

#include "lrd/io/tum_sequence.h"
#include "lrd/util/error.h"

namespace lrd::bag {

namespace fs = std::filesystem;

namespace {

// A topic's messages in stamp order (a recorder stores them in arrival order): their positions in
// bag order, and their stamps.
struct StampOrder {
  std::vector<std::size_t> index;
  std::vector<double> stamps;
};

StampOrder stamp_order(const fs::path& file, const std::string& topic, const std::vector<double>& stamps) {
  if (stamps.empty()) throw file_error(file, "topic " + topic + " has no messages");
  StampOrder out;
  out.index.resize(stamps.size());
  std::iota(out.index.begin(), out.index.end(), std::size_t{0});
  std::stable_sort(out.index.begin(), out.index.end(),
                   [&](std::size_t a, std::size_t b) { return stamps[a] < stamps[b]; });
  for (std::size_t k = 0; k < out.index.size(); ++k) {
    const double t = stamps[out.index[k]];
    if (k > 0 && t == out.stamps.back())
      throw file_error(file, fmt::format("topic {}: two messages stamped {:.9f}", topic, t));
    out.stamps.push_back(t);
  }
  return out;
}

}  // namespace

std::pair<std::string, std::string> parse_tf_pair(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size() ||
      text.find(':', colon + 1) != std::string::npos)
    throw lrd::Error("--gt-from-tf expects PARENT:CHILD (e.g. /world:/kinect), got '" + text + "'");
  return {text.substr(0, colon), text.substr(colon + 1)};
}

std::string list_topics(const TopicTypes& types) {
  if (types.empty()) return "the bag has no topics";
  std::string s = "the bag has";
  for (const auto& [topic, type] : types) s += fmt::format(" {} ({})", topic, type);
  return s;
}

lrd::Error wrong_type(const fs::path& file, const std::string& topic, const std::string& actual,
                      const std::string& expected) {
  return file_error(file, fmt::format("topic {} carries {}, expected {}", topic, actual, expected));
}

void require_topic(const fs::path& file, const std::string& topic, const TopicTypes& types,
                   const std::string& expected_type) {
  const auto it = types.find(topic);
  if (it == types.end()) throw file_error(file, "topic " + topic + " not found; " + list_topics(types));
  if (it->second != expected_type) throw wrong_type(file, topic, it->second, expected_type);
}

FramePairs pair_frames(const fs::path& file, const BagTopics& topics, const std::vector<double>& rgb_stamps,
                       const std::vector<double>& depth_stamps) {
  const StampOrder rgb = stamp_order(file, topics.rgb, rgb_stamps);
  const StampOrder depth = stamp_order(file, topics.depth, depth_stamps);
  const auto pairs = io::associate_timestamps(rgb.stamps, depth.stamps, topics.max_dt);
  if (pairs.empty())
    throw file_error(file, fmt::format("none of the {} messages on {} has a depth image on {} within {} s",
                                       rgb.stamps.size(), topics.rgb, topics.depth, topics.max_dt));
  FramePairs out;
  for (const auto& [i, j] : pairs) {
    // Named like the folder layout's files, so outputs named after frames match.
    out.entries.push_back({rgb.stamps[i], fs::path("rgb") / fmt::format("{:.6f}.png", rgb.stamps[i]),
                           depth.stamps[j], fs::path("depth") / fmt::format("{:.6f}.png", depth.stamps[j])});
    out.rgb.push_back(rgb.index[i]);
    out.depth.push_back(depth.index[j]);
  }
  return out;
}

void check_frame_size(const fs::path& file, const BagTopics& topics, const io::RgbdFrame& f) {
  if (f.rgb.size() != f.depth.size())
    throw file_error(
        file, fmt::format("{} at {:.6f} is {}x{} but its depth on {} is {}x{}", topics.rgb, f.timestamp,
                          f.rgb.cols, f.rgb.rows, topics.depth, f.depth.cols, f.depth.rows));
}

void check_camera_size(const fs::path& file, const BagTopics& topics, const io::RgbdFrame& f,
                       const std::optional<io::SourceCamera>& camera) {
  if (camera && (camera->width != f.rgb.cols || camera->height != f.rgb.rows))
    throw file_error(
        file, fmt::format("{} at {:.6f} is {}x{} but {} says {}x{}", topics.rgb, f.timestamp, f.rgb.cols,
                          f.rgb.rows, topics.camera_info, camera->width, camera->height));
}

}  // namespace lrd::bag
