#include "lrd/rosbag2/mcap_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "lrd/rosbag2/compression.h"
#include "lrd/rosbag2/mcap_records.h"

namespace lrd::rosbag2 {

namespace fs = std::filesystem;
using namespace mcap;

namespace {
constexpr std::size_t kRecordHead = 9;  // opcode, uint64 length
}  // namespace

lrd::Error McapReader::error(const std::string& problem) const {
  return file_error(file_, problem);
}

McapReader::McapReader(const fs::path& file) : file_(file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw error("MCAP file not found");
  size_ = fs::file_size(file, ec);
  in_.open(file, std::ios::binary);
  if (!in_ || ec) throw error("cannot open the MCAP file");
  std::uint8_t head[8] = {}, tail[8] = {};
  in_.read(reinterpret_cast<char*>(head), 8);
  if (size_ < 8 || std::memcmp(head, kMagic, 8) != 0)
    throw error("not an MCAP file (no MCAP magic at its start)");
  in_.seekg(static_cast<std::streamoff>(size_ - 8));
  in_.read(reinterpret_cast<char*>(tail), 8);
  if (size_ < 16 + kRecordHead || std::memcmp(tail, kMagic, 8) != 0)
    throw error(fmt::format("truncated MCAP file: its {} bytes do not end with the MCAP magic", size_));
  in_.seekg(8);
  pos_ = 8;
  data_crc_ = crc32(head, 8);
  scan();
}

bool McapReader::next_record(Record& r) {
  if (pos_ + kRecordHead > size_ - 8)
    throw error(fmt::format("truncated MCAP file: no data end or footer record before byte {}", size_));
  std::uint8_t head[kRecordHead];
  in_.seekg(static_cast<std::streamoff>(pos_));
  in_.read(reinterpret_cast<char*>(head), kRecordHead);
  std::uint64_t length;
  std::memcpy(&length, head + 1, 8);
  if (length > size_ - 8 - pos_ - kRecordHead)
    throw error(
        fmt::format("truncated MCAP file: the record (opcode 0x{:02x}) at byte {} needs {} bytes, the "
                    "file has {} after it",
                    head[0], pos_, length, size_ - pos_ - kRecordHead));
  r.opcode = head[0];
  r.offset = pos_;
  r.content.resize(length);
  in_.read(reinterpret_cast<char*>(r.content.data()), static_cast<std::streamsize>(length));
  if (!in_) throw error(fmt::format("cannot read the record at byte {}", pos_));
  if (r.opcode != kDataEnd) {
    data_crc_ = crc32(head, kRecordHead, data_crc_);
    data_crc_ = crc32(r.content.data(), r.content.size(), data_crc_);
  }
  pos_ += kRecordHead + length;
  return r.opcode != kDataEnd && r.opcode != kFooter;
}

void McapReader::scan() {
  Record r;
  bool first = true;
  while (next_record(r)) {
    if (first && r.opcode != kHeader) throw error("MCAP file does not start with a header record");
    first = false;
    try {
      if (r.opcode == kHeader) {
        FieldReader f(r.content.data(), r.content.size(), "header");
        profile_ = f.string();
      } else if (r.opcode == kChunk) {
        const std::vector<std::uint8_t> records = chunk_records(r);
        for (std::size_t at = 0; at < records.size();) {
          if (records.size() - at < kRecordHead) throw lrd::Error("a record runs past the chunk's end");
          std::uint64_t length;
          std::memcpy(&length, records.data() + at + 1, 8);
          if (length > records.size() - at - kRecordHead)
            throw lrd::Error("a record runs past the chunk's end");
          take_record(records[at], records.data() + at + kRecordHead, length, r.offset, at + kRecordHead);
          at += kRecordHead + length;
        }
      } else {
        take_record(r.opcode, r.content.data(), r.content.size(), 0, r.offset + kRecordHead);
      }
    } catch (const lrd::Error& e) {
      throw error(r.opcode == kChunk ? e.what() : fmt::format("record at byte {}: {}", r.offset, e.what()));
    }
  }
  if (r.opcode == kDataEnd) {
    FieldReader f(r.content.data(), r.content.size(), "data end");
    const std::uint32_t expected = f.u32();
    if (expected != 0 && expected != data_crc_)
      throw error(fmt::format("the data section's CRC is {:08x}, its data end record says {:08x}", data_crc_,
                              expected));
  }
}

std::vector<std::uint8_t> McapReader::chunk_records(const Record& chunk) const {
  FieldReader f(chunk.content.data(), chunk.content.size(), "chunk");
  (void)f.u64();  // message start time
  (void)f.u64();  // message end time
  const std::uint64_t uncompressed_size = f.u64();
  const std::uint32_t crc = f.u32();
  const std::string compression = f.string();
  std::size_t n = 0;
  const std::uint8_t* data = f.bytes(n, true);
  try {
    if (uncompressed_size > (std::uint64_t{1} << 34)) throw lrd::Error("implausible uncompressed size");
    std::vector<std::uint8_t> records =
        decompress(compression_from_name(compression), data, n, static_cast<std::size_t>(uncompressed_size));
    const std::uint32_t actual = crc32(records.data(), records.size());
    if (crc != 0 && actual != crc)
      throw lrd::Error(
          fmt::format("CRC mismatch: its records' CRC is {:08x}, the chunk says {:08x}", actual, crc));
    return records;
  } catch (const lrd::Error& e) {
    throw lrd::Error(fmt::format("chunk at byte {}: {}", chunk.offset, e.what()));
  }
}

void McapReader::take_record(std::uint8_t opcode, const std::uint8_t* data, std::size_t n,
                             std::uint64_t chunk_offset, std::uint64_t offset) {
  if (opcode == kSchema) {
    FieldReader f(data, n, "schema");
    const std::uint16_t id = f.u16();
    std::string name = f.string();
    schemas_[id] = {std::move(name), f.string()};
  } else if (opcode == kChannel) {
    FieldReader f(data, n, "channel");
    const std::uint16_t id = f.u16(), schema_id = f.u16();
    Channel c;
    c.topic = f.string();
    c.message_encoding = f.string();
    f.skip_map();
    if (schema_id != 0) {
      const auto s = schemas_.find(schema_id);
      if (s == schemas_.end())
        throw lrd::Error(fmt::format("channel {} names unknown schema {}", c.topic, schema_id));
      c.schema_name = s->second.first;
      c.schema_encoding = s->second.second;
    }
    // A ROS 2 message is CDR; any other encoding shows in the type (and fails the type check).
    topic_types_[c.topic] =
        c.message_encoding == "cdr" ? c.schema_name : c.schema_name + " in " + c.message_encoding;
    channels_[id] = std::move(c);
  } else if (opcode == kMessage) {
    FieldReader f(data, n, "message");
    const std::uint16_t channel = f.u16();
    (void)f.u32();  // sequence
    const std::uint64_t log_time = f.u64();
    (void)f.u64();  // publish time
    if (channels_.count(channel) == 0)
      throw lrd::Error(fmt::format("message on unknown channel {}", channel));
    std::size_t size = 0;
    const std::uint8_t* payload = f.rest(size);
    messages_[channel].push_back({chunk_offset, offset + static_cast<std::uint64_t>(payload - data), size,
                                  static_cast<std::int64_t>(log_time)});
  }
}

std::vector<MessageRef> McapReader::messages(const std::string& topic) const {
  std::vector<MessageRef> out;
  for (const auto& [id, channel] : channels_) {
    if (channel.topic != topic) continue;
    const auto m = messages_.find(id);
    if (m != messages_.end()) out.insert(out.end(), m->second.begin(), m->second.end());
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const MessageRef& x, const MessageRef& y) { return x.log_time_ns < y.log_time_ns; });
  return out;
}

const std::vector<std::uint8_t>& McapReader::cached_chunk(std::uint64_t offset) const {
  if (cached_offset_ != offset) {
    Record r;
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(offset));
    std::uint8_t head[kRecordHead];
    in_.read(reinterpret_cast<char*>(head), kRecordHead);
    std::uint64_t length;
    std::memcpy(&length, head + 1, 8);
    r.opcode = head[0];
    r.offset = offset;
    r.content.resize(length);
    in_.read(reinterpret_cast<char*>(r.content.data()), static_cast<std::streamsize>(length));
    if (!in_ || r.opcode != kChunk)
      throw error(fmt::format("cannot read the chunk at byte {} again", offset));
    try {
      cached_ = chunk_records(r);
    } catch (const lrd::Error& e) {
      throw error(e.what());
    }
    cached_offset_ = offset;
  }
  return cached_;
}

std::vector<std::uint8_t> McapReader::read(const MessageRef& ref) const {
  if (ref.a != 0) {
    const std::vector<std::uint8_t>& records = cached_chunk(ref.a);
    return {records.begin() + static_cast<std::ptrdiff_t>(ref.b),
            records.begin() + static_cast<std::ptrdiff_t>(ref.b + ref.c)};
  }
  std::vector<std::uint8_t> bytes(ref.c);
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(ref.b));
  in_.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!in_) throw error(fmt::format("cannot read the message at byte {}", ref.b));
  return bytes;
}

}  // namespace lrd::rosbag2
