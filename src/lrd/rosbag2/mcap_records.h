#pragma once
// MCAP's record layout (mcap.dev/spec, version 0): the magic, the opcodes, and little-endian
// builders and parsers of record fields (strings and byte arrays with a uint32 length, maps with a
// uint32 byte length), shared by the writer and the reader.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace lrd::rosbag2::mcap {

inline constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// A record's fields, appended in order.
class RecordBuilder {
 public:
  RecordBuilder& u8(std::uint8_t v) { return raw(&v, 1); }
  RecordBuilder& u16(std::uint16_t v) { return raw(&v, 2); }
  RecordBuilder& u32(std::uint32_t v) { return raw(&v, 4); }
  RecordBuilder& u64(std::uint64_t v) { return raw(&v, 8); }
  RecordBuilder& string(std::string_view s);
  RecordBuilder& bytes(const std::vector<std::uint8_t>& b);  // uint32 length + bytes
  RecordBuilder& raw(const void* data, std::size_t n);
  [[nodiscard]] const std::vector<std::uint8_t>& content() const { return bytes_; }
  [[nodiscard]] std::size_t size() const { return bytes_.size(); }

 private:
  std::vector<std::uint8_t> bytes_;
};

// opcode, uint64 length, content.
[[nodiscard]] std::vector<std::uint8_t> record(Opcode op, const RecordBuilder& content);

// Reads a record's fields; a field past the end is an lrd::Error naming the record.
class FieldReader {
 public:
  FieldReader(const std::uint8_t* data, std::size_t size, const char* record)
      : data_(data), size_(size), record_(record) {}
  [[nodiscard]] std::uint8_t u8();
  [[nodiscard]] std::uint16_t u16();
  [[nodiscard]] std::uint32_t u32();
  [[nodiscard]] std::uint64_t u64();
  [[nodiscard]] std::string string();
  // A uint32-length byte array (or, with a uint64 length, a chunk's records) in place.
  [[nodiscard]] const std::uint8_t* bytes(std::size_t& n, bool long_length = false);
  void skip_map();  // a uint32 byte length and its entries
  [[nodiscard]] std::size_t offset() const { return pos_; }
  [[nodiscard]] const std::uint8_t* rest(std::size_t& n);

 private:
  void need(std::size_t n) const;
  // A little-endian fixed-size field (MCAP's integers; x86-64 reads them as they are).
  template <typename T>
  T fixed();
  const std::uint8_t* data_;
  std::size_t size_, pos_ = 0;
  const char* record_;
};

[[nodiscard]] std::uint32_t crc32(const std::uint8_t* data, std::size_t n, std::uint32_t crc = 0);

}  // namespace lrd::rosbag2::mcap
