#include "lrd/bag/ros1_bag_structure.h"

#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::bag {

namespace {

constexpr char kMagic[] = "#ROSBAG V2.0\n";
constexpr std::uint64_t kMaxHeaderBytes = 16ull << 20;  // connection headers hold message definitions
enum Op : std::uint8_t {
  kMessage = 0x02,
  kBagHeader = 0x03,
  kIndex = 0x04,
  kChunk = 0x05,
  kChunkInfo = 0x06,
  kConnection = 0x07
};

[[noreturn]] void corrupt(const std::filesystem::path& file, const std::string& what) {
  throw Error(file.string() + ": cannot read the bag: " + what);
}

std::uint64_t little_endian(const std::string& bytes) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(bytes.data());
  return bytes.size() == 8 ? util::get_u64(p) : util::get_u32(p);
}

struct Record {
  std::uint64_t offset = 0;
  std::map<std::string, std::string> fields;
  std::uint64_t data_offset = 0, data_bytes = 0;
  [[nodiscard]] std::uint8_t op() const {
    const auto it = fields.find("op");
    return it != fields.end() && it->second.size() == 1 ? static_cast<std::uint8_t>(it->second[0]) : 0;
  }
  // A little-endian integer field of 4 or 8 bytes, or `fallback` when absent or of another size.
  [[nodiscard]] std::uint64_t number(const std::string& name, std::size_t bytes,
                                     std::uint64_t fallback) const {
    const auto it = fields.find(name);
    return it != fields.end() && it->second.size() == bytes ? little_endian(it->second) : fallback;
  }
};

class RecordReader {
 public:
  RecordReader(const std::filesystem::path& file) : file_(file), in_(file, std::ios::binary) {
    if (!in_) throw Error(file.string() + ": cannot read the bag: cannot open it");
    in_.seekg(0, std::ios::end);
    size_ = static_cast<std::uint64_t>(in_.tellg());
    char magic[sizeof kMagic - 1] = {};
    in_.seekg(0);
    if (size_ < sizeof magic || !in_.read(magic, sizeof magic) ||
        std::memcmp(magic, kMagic, sizeof magic) != 0)
      throw Error(file.string() + ": cannot read the bag: not a ROS 1 bag (no \"#ROSBAG V2.0\" line)");
  }
  [[nodiscard]] std::uint64_t size() const { return size_; }
  [[nodiscard]] std::string data(const Record& r) { return bytes(r.data_offset, r.data_bytes); }

  // The record at `offset`, which with its header fields and data must end by `end` (the file's
  // size, or the end of the chunk that holds it).
  Record read(std::uint64_t offset, std::uint64_t end) {
    const std::string limit = end == size_ ? "the file's end" : "its chunk's end";
    const std::string record = "record at byte " + std::to_string(offset);
    if (end - offset < 8) corrupt(file_, record + ": cut short by " + limit);
    Record r;
    r.offset = offset;
    const std::uint64_t header_bytes = u32_at(offset);
    if (header_bytes > kMaxHeaderBytes || header_bytes > end - offset - 8)
      corrupt(file_, record + " states a header of " + std::to_string(header_bytes) + " bytes past " + limit);
    const std::string header = bytes(offset + 4, header_bytes);
    for (std::size_t at = 0; at < header.size();) {
      if (header.size() - at < 4) corrupt(file_, record + ": a cut header field");
      const std::uint64_t n = little_endian(header.substr(at, 4));
      at += 4;
      if (n > header.size() - at) corrupt(file_, record + ": a header field past its header");
      const std::string field = header.substr(at, n);
      at += n;
      const std::size_t eq = field.find('=');
      if (eq == std::string::npos) corrupt(file_, record + ": a field without '='");
      r.fields[field.substr(0, eq)] = field.substr(eq + 1);
    }
    const std::uint64_t data_at = offset + 4 + header_bytes;
    r.data_bytes = u32_at(data_at);
    r.data_offset = data_at + 4;
    if (r.data_bytes > end - r.data_offset)
      corrupt(file_, record + " states " + std::to_string(r.data_bytes) + " bytes of data past " + limit);
    return r;
  }

 private:
  std::string bytes(std::uint64_t offset, std::uint64_t n) {
    std::string out(n, '\0');
    in_.seekg(static_cast<std::streamoff>(offset));
    in_.read(out.data(), static_cast<std::streamsize>(n));
    return out;
  }
  std::uint64_t u32_at(std::uint64_t offset) { return little_endian(bytes(offset, 4)); }

  std::filesystem::path file_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
};

// The offsets (from the chunk's data) of the records an uncompressed chunk holds, each inside the
// chunk: rosbag reads a message at an index entry's offset with the lengths stated there,
// unchecked against the chunk. Only the records' headers are read.
std::set<std::uint64_t> chunk_records(RecordReader& reader, const Record& chunk) {
  std::set<std::uint64_t> starts;
  const std::uint64_t end = chunk.data_offset + chunk.data_bytes;
  for (std::uint64_t at = chunk.data_offset; at < end;) {
    const Record r = reader.read(at, end);
    starts.insert(at - chunk.data_offset);
    at = r.data_offset + r.data_bytes;
  }
  return starts;
}

// An index record's entries (12 bytes each: time, offset) name records of its chunk.
void check_index(const std::filesystem::path& file, const Record& index, const std::string& bytes,
                 const std::set<std::uint64_t>& records) {
  const std::uint64_t count = index.number("count", 4, ~0ull);
  if (count == ~0ull || count * 12 != bytes.size())
    corrupt(file, "index at byte " + std::to_string(index.offset) + " holds " + std::to_string(bytes.size()) +
                      " bytes for its count of entries");
  for (std::uint64_t k = 0; k < count; ++k)
    if (records.count(little_endian(bytes.substr(k * 12 + 8, 4))) == 0)
      corrupt(file,
              "index at byte " + std::to_string(index.offset) + " names a message where its chunk has none");
}

void check_chunk(const std::filesystem::path& file, const Record& r) {
  const auto compression = r.fields.find("compression");
  const std::uint64_t size = r.number("size", 4, ~0ull);
  if (compression == r.fields.end() || size == ~0ull)
    corrupt(file, "chunk at byte " + std::to_string(r.offset) + " without its compression or size");
  if (size > kMaxRos1ChunkBytes)
    corrupt(file, "chunk at byte " + std::to_string(r.offset) + " states " + std::to_string(size) +
                      " bytes uncompressed (at most " + std::to_string(kMaxRos1ChunkBytes) + ")");
  if (compression->second == "none" && size != r.data_bytes)
    corrupt(file, "uncompressed chunk at byte " + std::to_string(r.offset) + " states " +
                      std::to_string(size) + " bytes but holds " + std::to_string(r.data_bytes));
}

}  // namespace

void check_ros1_bag_structure(const std::filesystem::path& file) {
  RecordReader reader(file);
  const Record header = reader.read(sizeof kMagic - 1, reader.size());
  if (header.op() != kBagHeader) corrupt(file, "no bag header record after the version line");
  const std::uint64_t index_pos = header.number("index_pos", 8, 0);
  const std::uint64_t connections = header.number("conn_count", 4, ~0ull);
  const std::uint64_t chunks = header.number("chunk_count", 4, ~0ull);
  if (connections == ~0ull || chunks == ~0ull) corrupt(file, "the bag header lacks its counts");
  if (index_pos == 0) corrupt(file, "not indexed (cut short while recording? `rosbag reindex` repairs it)");

  std::set<std::uint64_t> chunk_offsets;
  std::optional<std::set<std::uint64_t>> last_chunk_records;  // empty: the last chunk is compressed
  std::uint64_t connection_records = 0, chunk_infos = 0;
  bool index_found = false;
  for (std::uint64_t at = header.data_offset + header.data_bytes; at < reader.size();) {
    if (at == index_pos) index_found = true;
    const Record r = reader.read(at, reader.size());
    switch (r.op()) {
      case kChunk:
        check_chunk(file, r);
        chunk_offsets.insert(r.offset);
        last_chunk_records.reset();
        // Compressed chunks are not looked into: that would mean decompressing the whole bag.
        if (r.fields.at("compression") == "none") last_chunk_records = chunk_records(reader, r);
        break;
      case kConnection:
        connection_records += at >= index_pos ? 1 : 0;
        break;
      case kChunkInfo: {
        ++chunk_infos;
        const std::uint64_t chunk_pos = r.number("chunk_pos", 8, ~0ull);
        if (chunk_offsets.count(chunk_pos) == 0)
          corrupt(file, "the index names a chunk at byte " + std::to_string(chunk_pos) + " where none is");
        break;
      }
      case kIndex:
        if (at < index_pos && last_chunk_records) check_index(file, r, reader.data(r), *last_chunk_records);
        break;
      case kMessage:
        break;
      default:
        corrupt(file, "record at byte " + std::to_string(r.offset) + " of unknown kind");
    }
    at = r.data_offset + r.data_bytes;
  }
  if (!index_found && !(index_pos == reader.size() && connections == 0 && chunks == 0))
    corrupt(file, "the index position " + std::to_string(index_pos) +
                      " is not a record of the file (cut short? `rosbag reindex` repairs it)");
  if (connection_records < connections || chunk_infos < chunks)
    corrupt(file, "the index holds " + std::to_string(connection_records) + " connections and " +
                      std::to_string(chunk_infos) + " chunks, the bag header counts " +
                      std::to_string(connections) + " and " + std::to_string(chunks));
}

}  // namespace lrd::bag
