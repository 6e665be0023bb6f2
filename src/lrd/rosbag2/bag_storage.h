#pragma once
// A rosbag2 bag's storage as the sequence reader sees it, whatever the format (MCAP, sqlite3):
// its topics with their types, each topic's messages in record order, and a message's bytes read
// on demand (so a bag is never held in memory).
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace lrd::rosbag2 {

// Where a message is in its storage (meaningful to that storage only).
struct MessageRef {
  std::uint64_t a = 0, b = 0, c = 0;
  std::int64_t log_time_ns = 0;
  friend bool operator<(const MessageRef& x, const MessageRef& y) {
    return std::tie(x.a, x.b) < std::tie(y.a, y.b);
  }
};

class BagStorage {
 public:
  virtual ~BagStorage() = default;
  // The file named in errors.
  [[nodiscard]] virtual const std::filesystem::path& file() const = 0;
  // Topic -> ROS 2 type name ("sensor_msgs/msg/Image").
  [[nodiscard]] virtual const std::map<std::string, std::string>& topics() const = 0;
  // The topic's messages by record time (in file order for equal times).
  [[nodiscard]] virtual std::vector<MessageRef> messages(const std::string& topic) const = 0;
  // A message's serialised bytes (CDR); throws lrd::Error naming the file. Reading in ref order
  // is fastest (an MCAP chunk is decompressed once). Called from one thread at a time.
  [[nodiscard]] virtual std::vector<std::uint8_t> read(const MessageRef& ref) const = 0;
};

// Opens a bag by what the path is: a .mcap file, a .db3 file, or a rosbag2 folder whose
// metadata.yaml names the storage ("mcap" or "sqlite3") and its one file. Throws lrd::Error
// naming the path and the problem.
[[nodiscard]] std::unique_ptr<BagStorage> open_storage(const std::filesystem::path& path);

}  // namespace lrd::rosbag2
