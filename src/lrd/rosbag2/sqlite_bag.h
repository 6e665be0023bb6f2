#pragma once
// rosbag2's sqlite3 storage (a .db3 file) through SQLite's C API: the `topics` table (id, name,
// type, serialization_format, offered_qos_profiles) and the `messages` table (id, topic_id,
// timestamp, data), as rosbag2's sqlite3 plugin lays them out.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "lrd/rosbag2/bag_storage.h"
#include "lrd/util/atomic_file.h"

struct sqlite3;
struct sqlite3_stmt;

namespace lrd::rosbag2 {

class Sqlite3Reader final : public BagStorage {
 public:
  // Opens read-only and reads the topics; throws lrd::Error naming the file for a missing,
  // truncated or foreign database.
  explicit Sqlite3Reader(const std::filesystem::path& file);
  ~Sqlite3Reader() override;
  Sqlite3Reader(const Sqlite3Reader&) = delete;
  Sqlite3Reader& operator=(const Sqlite3Reader&) = delete;

  [[nodiscard]] const std::filesystem::path& file() const override { return file_; }
  [[nodiscard]] const std::map<std::string, std::string>& topics() const override { return topic_types_; }
  [[nodiscard]] std::vector<MessageRef> messages(const std::string& topic) const override;
  [[nodiscard]] std::vector<std::uint8_t> read(const MessageRef& ref) const override;

 private:
  void read_topics();  // the topics table into topic_types_ and topic_ids_
  std::filesystem::path file_;
  sqlite3* db_ = nullptr;
  std::map<std::string, std::string> topic_types_;
  std::map<std::string, std::int64_t> topic_ids_;
};

// A topic as rosbag2 records it.
struct TopicInfo {
  std::string name, type, serialization_format = "cdr";
};

// Writes a .db3 (beside its name, renamed into place by close(); an unclosed writer removes it).
class Sqlite3Writer {
 public:
  explicit Sqlite3Writer(const std::filesystem::path& file);
  ~Sqlite3Writer();
  Sqlite3Writer(const Sqlite3Writer&) = delete;
  Sqlite3Writer& operator=(const Sqlite3Writer&) = delete;

  std::int64_t add_topic(const TopicInfo& topic);
  void write(std::int64_t topic_id, std::int64_t timestamp_ns, const std::vector<std::uint8_t>& data);
  void close();

 private:
  void exec(const char* sql);
  std::filesystem::path file_;
  util::AtomicFile out_;  // sqlite3 writes the temporary by name
  sqlite3* db_ = nullptr;
  sqlite3_stmt* insert_ = nullptr;
  std::int64_t next_topic_ = 1;
};

}  // namespace lrd::rosbag2
