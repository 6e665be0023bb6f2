#pragma once
// Writes an MCAP file (mcap.dev/spec) as ROS 2's MCAP storage does and standard readers expect:
// the "ros2" profile, schemas and channels, messages in chunks (zstd-compressed by default) each
// followed by its message indexes, then the summary (schemas, channels, statistics, chunk
// indexes) with its summary offsets and the footer, every CRC filled in. The file is written
// beside its name and renamed into place by close(); an unclosed writer removes it.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "lrd/rosbag2/compression.h"
#include "lrd/util/atomic_file.h"

namespace lrd::rosbag2 {

struct McapWriterOptions {
  Compression compression = Compression::zstd;
  std::size_t chunk_size = 4u << 20;  // uncompressed bytes of records before a chunk is closed
  std::string profile = "ros2";
};

class McapWriter {
 public:
  // Throws lrd::Error naming the file when it cannot be created.
  McapWriter(const std::filesystem::path& file, McapWriterOptions options = {});
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // Ids count from 1 (a schema id of 0 means "no schema").
  std::uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  std::uint16_t add_channel(std::uint16_t schema_id, const std::string& topic,
                            const std::string& message_encoding);
  void write(std::uint16_t channel_id, std::uint64_t log_time_ns, const std::vector<std::uint8_t>& data);
  // Writes the rest and renames the file into place; throws lrd::Error naming the file.
  void close();

 private:
  struct ChunkIndex {
    std::uint64_t start_time, end_time, offset, length, message_index_length, compressed, uncompressed;
    std::map<std::uint16_t, std::uint64_t> message_index_offsets;
  };
  void put(const std::vector<std::uint8_t>& bytes);
  void flush_chunk();
  void write_summary();

  McapWriterOptions options_;
  util::AtomicFile out_;
  std::uint64_t offset_ = 0;
  std::uint32_t data_crc_ = 0;  // of everything written so far, until the data end record
  bool closed_ = false;

  std::vector<std::vector<std::uint8_t>> schemas_, channels_;  // their records, for the summary
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint64_t messages_ = 0, start_time_ = 0, end_time_ = 0;
  std::vector<ChunkIndex> chunk_indexes_;
  // The open chunk: its records, time span and each channel's (log time, offset) entries.
  std::vector<std::uint8_t> chunk_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_entries_;
  std::map<std::uint16_t, std::uint32_t> sequence_;
};

}  // namespace lrd::rosbag2
