#include "lrd/rosbag2/mcap_records.h"

#include <fmt/format.h>
#include <zlib.h>

#include <cstring>

#include "lrd/util/error.h"

namespace lrd::rosbag2::mcap {

RecordBuilder& RecordBuilder::raw(const void* data, std::size_t n) {
  const auto* p = static_cast<const std::uint8_t*>(data);
  bytes_.insert(bytes_.end(), p, p + n);
  return *this;
}

RecordBuilder& RecordBuilder::string(std::string_view s) {
  u32(static_cast<std::uint32_t>(s.size()));
  return raw(s.data(), s.size());
}

RecordBuilder& RecordBuilder::bytes(const std::vector<std::uint8_t>& b) {
  u32(static_cast<std::uint32_t>(b.size()));
  return raw(b.data(), b.size());
}

std::vector<std::uint8_t> record(Opcode op, const RecordBuilder& content) {
  RecordBuilder r;
  r.u8(op).u64(content.size()).raw(content.content().data(), content.size());
  return r.content();
}

void FieldReader::need(std::size_t n) const {
  if (n > size_ - pos_)
    throw lrd::Error(fmt::format("{} record of {} bytes ends inside a field (needs {} bytes at {})", record_,
                                 size_, n, pos_));
}

std::uint8_t FieldReader::u8() {
  need(1);
  return data_[pos_++];
}

template <typename T>
T FieldReader::fixed() {
  need(sizeof(T));
  T v;
  std::memcpy(&v, data_ + pos_, sizeof(T));
  pos_ += sizeof(T);
  return v;
}

std::uint16_t FieldReader::u16() {
  return fixed<std::uint16_t>();
}

std::uint32_t FieldReader::u32() {
  return fixed<std::uint32_t>();
}

std::uint64_t FieldReader::u64() {
  return fixed<std::uint64_t>();
}

std::string FieldReader::string() {
  std::size_t n = 0;
  const std::uint8_t* p = bytes(n);
  return {reinterpret_cast<const char*>(p), n};
}

const std::uint8_t* FieldReader::bytes(std::size_t& n, bool long_length) {
  n = long_length ? u64() : u32();
  need(n);
  const std::uint8_t* p = data_ + pos_;
  pos_ += n;
  return p;
}

void FieldReader::skip_map() {
  std::size_t n = 0;
  (void)bytes(n);
}

const std::uint8_t* FieldReader::rest(std::size_t& n) {
  n = size_ - pos_;
  const std::uint8_t* p = data_ + pos_;
  pos_ = size_;
  return p;
}

std::uint32_t crc32(const std::uint8_t* data, std::size_t n, std::uint32_t crc) {
  // zlib's crc32 takes a uInt length: feed it in pieces.
  while (n > 0) {
    const auto piece = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
    crc = static_cast<std::uint32_t>(::crc32(crc, data, piece));
    data += piece;
    n -= piece;
  }
  return crc;
}

}  // namespace lrd::rosbag2::mcap
