#include "lrd/rosbag2/mcap_writer.h"

#include <fmt/format.h>

#include <algorithm>

#include "lrd/rosbag2/mcap_records.h"
#include "lrd/util/error.h"

namespace lrd::rosbag2 {

namespace fs = std::filesystem;
using namespace mcap;

McapWriter::McapWriter(const fs::path& file, McapWriterOptions options)
    : options_(std::move(options)), out_(file) {
  put({std::begin(kMagic), std::end(kMagic)});
  RecordBuilder header;
  header.string(options_.profile).string("lrd-slam");
  put(record(kHeader, header));
}

McapWriter::~McapWriter() = default;

void McapWriter::put(const std::vector<std::uint8_t>& bytes) {
  out_.write({reinterpret_cast<const char*>(bytes.data()), bytes.size()});
  data_crc_ = crc32(bytes.data(), bytes.size(), data_crc_);
  offset_ += bytes.size();
}

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding,
                                     const std::string& data) {
  const auto id = static_cast<std::uint16_t>(schemas_.size() + 1);
  RecordBuilder b;
  b.u16(id).string(name).string(encoding).bytes({data.begin(), data.end()});
  schemas_.push_back(record(kSchema, b));
  put(schemas_.back());
  return id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema_id, const std::string& topic,
                                      const std::string& message_encoding) {
  const auto id = static_cast<std::uint16_t>(channels_.size() + 1);
  RecordBuilder b;
  b.u16(id).u16(schema_id).string(topic).string(message_encoding).u32(0);  // no metadata
  channels_.push_back(record(kChannel, b));
  channel_counts_[id] = 0;
  put(channels_.back());
  return id;
}

void McapWriter::write(std::uint16_t channel_id, std::uint64_t log_time_ns,
                       const std::vector<std::uint8_t>& data) {
  RecordBuilder b;
  b.u16(channel_id)
      .u32(sequence_[channel_id]++)
      .u64(log_time_ns)
      .u64(log_time_ns)
      .raw(data.data(), data.size());
  const std::vector<std::uint8_t> message = record(kMessage, b);
  if (chunk_entries_.empty()) chunk_start_ = chunk_end_ = log_time_ns;
  chunk_start_ = std::min(chunk_start_, log_time_ns);
  chunk_end_ = std::max(chunk_end_, log_time_ns);
  chunk_entries_[channel_id].emplace_back(log_time_ns, chunk_.size());
  chunk_.insert(chunk_.end(), message.begin(), message.end());
  if (messages_ == 0) start_time_ = end_time_ = log_time_ns;
  start_time_ = std::min(start_time_, log_time_ns);
  end_time_ = std::max(end_time_, log_time_ns);
  ++messages_;
  ++channel_counts_[channel_id];
  if (chunk_.size() >= options_.chunk_size) flush_chunk();
}

void McapWriter::flush_chunk() {
  if (chunk_entries_.empty()) return;
  const std::vector<std::uint8_t> compressed = compress(options_.compression, chunk_);
  RecordBuilder b;
  b.u64(chunk_start_).u64(chunk_end_).u64(chunk_.size()).u32(crc32(chunk_.data(), chunk_.size()));
  b.string(compression_name(options_.compression))
      .u64(compressed.size())
      .raw(compressed.data(), compressed.size());
  ChunkIndex index{chunk_start_, chunk_end_, offset_, 0, 0, compressed.size(), chunk_.size(), {}};
  put(record(kChunk, b));
  index.length = offset_ - index.offset;
  const std::uint64_t indexes_start = offset_;
  for (auto& [channel, entries] : chunk_entries_) {
    // Entries in log-time order (the readers binary-search them).
    std::stable_sort(entries.begin(), entries.end());
    RecordBuilder m;
    m.u16(channel).u32(static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [time, offset] : entries) m.u64(time).u64(offset);
    index.message_index_offsets[channel] = offset_;
    put(record(kMessageIndex, m));
  }
  index.message_index_length = offset_ - indexes_start;
  chunk_indexes_.push_back(std::move(index));
  chunk_.clear();
  chunk_entries_.clear();
}

void McapWriter::write_summary() {
  const std::uint64_t summary_start = offset_;
  std::uint32_t summary_crc = 0;
  const auto put_summary = [&](const std::vector<std::uint8_t>& bytes) {
    summary_crc = crc32(bytes.data(), bytes.size(), summary_crc);
    put(bytes);
  };
  // Each group's (opcode, start, length), for the summary offsets.
  std::vector<std::tuple<Opcode, std::uint64_t, std::uint64_t>> groups;
  const auto group = [&](Opcode op, const std::vector<std::vector<std::uint8_t>>& records) {
    if (records.empty()) return;
    const std::uint64_t start = offset_;
    for (const auto& r : records) put_summary(r);
    groups.emplace_back(op, start, offset_ - start);
  };
  group(kSchema, schemas_);
  group(kChannel, channels_);
  RecordBuilder s;
  s.u64(messages_)
      .u16(static_cast<std::uint16_t>(schemas_.size()))
      .u32(static_cast<std::uint32_t>(channels_.size()));
  s.u32(0).u32(0).u32(static_cast<std::uint32_t>(chunk_indexes_.size())).u64(start_time_).u64(end_time_);
  s.u32(static_cast<std::uint32_t>(channel_counts_.size() * 10));
  for (const auto& [channel, count] : channel_counts_) s.u16(channel).u64(count);
  group(kStatistics, {record(kStatistics, s)});
  std::vector<std::vector<std::uint8_t>> indexes;
  for (const ChunkIndex& c : chunk_indexes_) {
    RecordBuilder b;
    b.u64(c.start_time).u64(c.end_time).u64(c.offset).u64(c.length);
    b.u32(static_cast<std::uint32_t>(c.message_index_offsets.size() * 10));
    for (const auto& [channel, offset] : c.message_index_offsets) b.u16(channel).u64(offset);
    b.u64(c.message_index_length)
        .string(compression_name(options_.compression))
        .u64(c.compressed)
        .u64(c.uncompressed);
    indexes.push_back(record(kChunkIndex, b));
  }
  group(kChunkIndex, indexes);
  const std::uint64_t summary_offset_start = offset_;
  for (const auto& [op, start, length] : groups) {
    RecordBuilder b;
    b.u8(op).u64(start).u64(length);
    put_summary(record(kSummaryOffset, b));
  }
  RecordBuilder footer;
  footer.u64(summary_start).u64(summary_offset_start);
  std::vector<std::uint8_t> footer_record = record(kFooter, RecordBuilder(footer).u32(0));
  // The summary CRC covers the footer up to its own field.
  summary_crc = crc32(footer_record.data(), footer_record.size() - 4, summary_crc);
  std::copy_n(reinterpret_cast<const std::uint8_t*>(&summary_crc), 4, footer_record.end() - 4);
  put(footer_record);
  put({std::begin(kMagic), std::end(kMagic)});
}

void McapWriter::close() {
  if (closed_) return;
  flush_chunk();
  RecordBuilder end;
  end.u32(data_crc_);
  put(record(kDataEnd, end));
  write_summary();
  out_.commit();
  closed_ = true;
}

}  // namespace lrd::rosbag2
