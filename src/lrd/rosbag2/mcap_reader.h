#pragma once
// Reads an MCAP file as rosbag2 writes it (and as other MCAP writers do): every record from the
// start, chunks decompressed ("", "zstd", "lz4") and their CRCs checked, the data section's CRC
// checked, so a truncated or corrupted file is an lrd::Error naming the file and the record.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "lrd/rosbag2/bag_storage.h"
#include "lrd/util/error.h"

namespace lrd::rosbag2 {

class McapReader final : public BagStorage {
 public:
  // Reads every record (not the messages' bytes kept: they are read again on demand).
  explicit McapReader(const std::filesystem::path& file);

  [[nodiscard]] const std::filesystem::path& file() const override { return file_; }
  [[nodiscard]] const std::map<std::string, std::string>& topics() const override { return topic_types_; }
  [[nodiscard]] std::vector<MessageRef> messages(const std::string& topic) const override;
  [[nodiscard]] std::vector<std::uint8_t> read(const MessageRef& ref) const override;

  struct Channel {
    std::string topic, message_encoding, schema_name, schema_encoding;
  };
  [[nodiscard]] const std::map<std::uint16_t, Channel>& channels() const { return channels_; }
  [[nodiscard]] const std::string& profile() const { return profile_; }

 private:
  // A record read from the file: its opcode, offset and content.
  struct Record {
    std::uint8_t opcode = 0;
    std::uint64_t offset = 0;
    std::vector<std::uint8_t> content;
  };
  [[nodiscard]] bool next_record(Record& r);
  void scan();
  // The records inside a chunk (or, for outer_offset 0, one record outside any).
  void take_record(std::uint8_t opcode, const std::uint8_t* data, std::size_t n, std::uint64_t chunk_offset,
                   std::uint64_t offset_in_chunk);
  // The chunk's records decompressed and checked; lrd::Error "chunk at byte N: problem".
  [[nodiscard]] std::vector<std::uint8_t> chunk_records(const Record& chunk) const;
  [[nodiscard]] const std::vector<std::uint8_t>& cached_chunk(std::uint64_t offset) const;
  [[nodiscard]] lrd::Error error(const std::string& problem) const;

  std::filesystem::path file_;
  mutable std::ifstream in_;
  std::uint64_t size_ = 0, pos_ = 0;
  std::uint32_t data_crc_ = 0;  // of the bytes read before the data end record
  std::string profile_;
  std::map<std::uint16_t, std::pair<std::string, std::string>> schemas_;  // id -> name, encoding
  std::map<std::uint16_t, Channel> channels_;
  std::map<std::string, std::string> topic_types_;
  std::map<std::uint16_t, std::vector<MessageRef>> messages_;  // by channel
  mutable std::uint64_t cached_offset_ = 0;
  mutable std::vector<std::uint8_t> cached_;
};

}  // namespace lrd::rosbag2
