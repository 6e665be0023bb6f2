#include "lrd/rosbag2/sqlite_bag.h"

#include <fmt/format.h>
#include <sqlite3.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <memory>

#include "lrd/util/error.h"

namespace lrd::rosbag2 {

namespace fs = std::filesystem;

namespace {

using Statement = std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)>;

Statement prepare(sqlite3* db, const fs::path& file, const char* sql) {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(db, sql, -1, &s, nullptr) != SQLITE_OK) {
    sqlite3_finalize(s);
    throw file_error(file, fmt::format("not a rosbag2 sqlite3 bag ({})", sqlite3_errmsg(db)));
  }
  return {s, &sqlite3_finalize};
}

// SQLite reads a truncated file's missing pages as errors only when it reaches them: the header's
// page count against the file's size says so at once.
void check_not_truncated(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  unsigned char header[100] = {};
  in.read(reinterpret_cast<char*>(header), sizeof header);
  if (in.gcount() < static_cast<std::streamsize>(sizeof header) ||
      std::memcmp(header, "SQLite format 3", 16) != 0)
    throw file_error(file, "not a SQLite database (a rosbag2 .db3 file)");
  std::uint32_t page_size = (header[16] << 8) | header[17];
  if (page_size == 1) page_size = 65536;
  const std::uint32_t pages =
      (std::uint32_t{header[28]} << 24) | (header[29] << 16) | (header[30] << 8) | header[31];
  const std::uint64_t expected = std::uint64_t{page_size} * pages, actual = fs::file_size(file);
  if (pages > 0 && actual < expected)
    throw file_error(file, fmt::format("truncated SQLite database: {} bytes of its {} pages of {} ({} bytes)",
                                       actual, pages, page_size, expected));
}

}  // namespace

Sqlite3Reader::Sqlite3Reader(const fs::path& file) : file_(file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw file_error(file, "sqlite3 bag file not found");
  check_not_truncated(file);
  // The destructor does not run for a constructor that throws: the connection is closed here
  // (sqlite3_open_v2 returns one even when it fails).
  try {
    if (sqlite3_open_v2(file.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK)
      throw file_error(file, fmt::format("cannot open the sqlite3 bag: {}", sqlite3_errmsg(db_)));
    read_topics();
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

void Sqlite3Reader::read_topics() {
  const Statement topics = prepare(db_, file_, "SELECT id, name, type FROM topics");
  int rc;
  while ((rc = sqlite3_step(topics.get())) == SQLITE_ROW) {
    const auto text = [&](int column) {
      const unsigned char* t = sqlite3_column_text(topics.get(), column);
      return t ? std::string(reinterpret_cast<const char*>(t)) : std::string();
    };
    topic_types_[text(1)] = text(2);
    topic_ids_[text(1)] = sqlite3_column_int64(topics.get(), 0);
  }
  if (rc != SQLITE_DONE)
    throw file_error(file_, fmt::format("cannot read the topics: {}", sqlite3_errmsg(db_)));
}

Sqlite3Reader::~Sqlite3Reader() {
  sqlite3_close(db_);
}

std::vector<MessageRef> Sqlite3Reader::messages(const std::string& topic) const {
  std::vector<MessageRef> out;
  const auto id = topic_ids_.find(topic);
  if (id == topic_ids_.end()) return out;
  const Statement s =
      prepare(db_, file_, "SELECT id, timestamp FROM messages WHERE topic_id = ? ORDER BY timestamp, id");
  sqlite3_bind_int64(s.get(), 1, id->second);
  int rc;
  while ((rc = sqlite3_step(s.get())) == SQLITE_ROW) {
    MessageRef r;
    r.a = static_cast<std::uint64_t>(sqlite3_column_int64(s.get(), 0));
    r.log_time_ns = sqlite3_column_int64(s.get(), 1);
    out.push_back(r);
  }
  if (rc != SQLITE_DONE)
    throw file_error(file_, fmt::format("cannot read the messages of {}: {}", topic, sqlite3_errmsg(db_)));
  return out;
}

std::vector<std::uint8_t> Sqlite3Reader::read(const MessageRef& ref) const {
  const Statement s = prepare(db_, file_, "SELECT data FROM messages WHERE id = ?");
  sqlite3_bind_int64(s.get(), 1, static_cast<std::int64_t>(ref.a));
  if (sqlite3_step(s.get()) != SQLITE_ROW)
    throw file_error(file_, fmt::format("cannot read message {}: {}", ref.a, sqlite3_errmsg(db_)));
  const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(s.get(), 0));
  const int n = sqlite3_column_bytes(s.get(), 0);
  return data ? std::vector<std::uint8_t>(data, data + n) : std::vector<std::uint8_t>();
}

Sqlite3Writer::Sqlite3Writer(const fs::path& file) : file_(file), out_(file) {
  if (sqlite3_open_v2(out_.temporary().c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK)
    throw file_error(file_, fmt::format("cannot create the sqlite3 bag: {}", sqlite3_errmsg(db_)));
  // rosbag2's (humble) schema; one transaction for the whole bag.
  exec(
      "PRAGMA journal_mode=MEMORY; PRAGMA synchronous=OFF;"
      "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
      "INSERT INTO schema VALUES (3, 'humble');"
      "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
      " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL,"
      " data BLOB NOT NULL);"
      "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
      "BEGIN TRANSACTION;");
  if (sqlite3_prepare_v2(db_, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", -1,
                         &insert_, nullptr) != SQLITE_OK)
    throw file_error(file_, fmt::format("cannot write the sqlite3 bag: {}", sqlite3_errmsg(db_)));
}

Sqlite3Writer::~Sqlite3Writer() {
  sqlite3_finalize(insert_);
  if (db_ != nullptr) sqlite3_close(db_);  // then out_ removes the temporary
}

void Sqlite3Writer::exec(const char* sql) {
  char* message = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string text = message ? message : "unknown error";
    sqlite3_free(message);
    throw file_error(file_, "cannot write the sqlite3 bag: " + text);
  }
}

std::int64_t Sqlite3Writer::add_topic(const TopicInfo& topic) {
  const Statement s = prepare(db_, file_,
                              "INSERT INTO topics (id, name, type, serialization_format, "
                              "offered_qos_profiles) VALUES (?, ?, ?, ?, '')");
  const std::int64_t id = next_topic_++;
  sqlite3_bind_int64(s.get(), 1, id);
  sqlite3_bind_text(s.get(), 2, topic.name.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(s.get(), 3, topic.type.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(s.get(), 4, topic.serialization_format.c_str(), -1, SQLITE_TRANSIENT);
  if (sqlite3_step(s.get()) != SQLITE_DONE)
    throw file_error(file_, fmt::format("cannot write the topic {}: {}", topic.name, sqlite3_errmsg(db_)));
  return id;
}

void Sqlite3Writer::write(std::int64_t topic_id, std::int64_t timestamp_ns,
                          const std::vector<std::uint8_t>& data) {
  sqlite3_reset(insert_);
  sqlite3_bind_int64(insert_, 1, topic_id);
  sqlite3_bind_int64(insert_, 2, timestamp_ns);
  sqlite3_bind_blob64(insert_, 3, data.data(), data.size(), SQLITE_STATIC);
  if (sqlite3_step(insert_) != SQLITE_DONE)
    throw file_error(file_, fmt::format("cannot write a message: {}", sqlite3_errmsg(db_)));
}

void Sqlite3Writer::close() {
  exec("COMMIT;");
  sqlite3_finalize(insert_);
  insert_ = nullptr;
  if (sqlite3_close(db_) != SQLITE_OK) throw file_error(file_, "cannot close the sqlite3 bag");
  db_ = nullptr;
  out_.commit();
}

}  // namespace lrd::rosbag2
