#include "lrd/rosbag2/cdr.h"

#include <fmt/format.h>

#include <bit>
#include <cstring>

#include "lrd/util/error.h"

namespace lrd::rosbag2 {

static_assert(std::endian::native == std::endian::little, "CDR here is written and read little-endian");

namespace {
constexpr std::size_t kHeaderSize = 4;  // encapsulation: 00 01 (CDR_LE), 00 00 (options)
}  // namespace

CdrWriter::CdrWriter() : bytes_{0x00, 0x01, 0x00, 0x00} {}

void CdrWriter::align(std::size_t n) {
  const std::size_t offset = bytes_.size() - kHeaderSize;
  bytes_.resize(bytes_.size() + (n - offset % n) % n, 0);
}

void CdrWriter::raw(const void* data, std::size_t size) {
  const auto* p = static_cast<const std::uint8_t*>(data);
  bytes_.insert(bytes_.end(), p, p + size);
}

void CdrWriter::u32(std::uint32_t v) {
  align(4);
  raw(&v, 4);
}

void CdrWriter::i32(std::int32_t v) {
  align(4);
  raw(&v, 4);
}

void CdrWriter::f64(double v) {
  align(8);
  raw(&v, 8);
}

void CdrWriter::string(std::string_view s) {
  u32(static_cast<std::uint32_t>(s.size() + 1));
  raw(s.data(), s.size());
  u8(0);
}

void CdrWriter::sequence_length(std::size_t n) {
  u32(static_cast<std::uint32_t>(n));
}

void CdrWriter::byte_sequence(const std::uint8_t* data, std::size_t size) {
  sequence_length(size);
  raw(data, size);
}

void CdrWriter::f64_array(const double* values, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) f64(values[i]);
}

CdrReader::CdrReader(const std::uint8_t* data, std::size_t size)
    : data_(data), size_(size), pos_(kHeaderSize) {
  if (size < kHeaderSize)
    throw lrd::Error(fmt::format("CDR message of {} bytes has no encapsulation header", size));
  if (data[0] != 0x00 || data[1] != 0x01)
    throw lrd::Error(fmt::format("CDR encapsulation {:02x} {:02x} is not little-endian plain CDR (00 01)",
                                 data[0], data[1]));
}

void CdrReader::need(std::size_t n, const char* field) const {
  if (n > size_ - pos_)
    throw lrd::Error(fmt::format("CDR message of {} bytes ends inside '{}' (needs {} bytes at offset {})",
                                 size_, field, n, pos_));
}

void CdrReader::align(std::size_t n, const char* field) {
  const std::size_t pad = (n - (pos_ - kHeaderSize) % n) % n;
  need(pad, field);
  pos_ += pad;
}

std::uint8_t CdrReader::u8(const char* field) {
  need(1, field);
  return data_[pos_++];
}

std::uint32_t CdrReader::u32(const char* field) {
  align(4, field);
  need(4, field);
  std::uint32_t v;
  std::memcpy(&v, data_ + pos_, 4);
  pos_ += 4;
  return v;
}

std::int32_t CdrReader::i32(const char* field) {
  return static_cast<std::int32_t>(u32(field));
}

double CdrReader::f64(const char* field) {
  align(8, field);
  need(8, field);
  double v;
  std::memcpy(&v, data_ + pos_, 8);
  pos_ += 8;
  return v;
}

std::string CdrReader::string(const char* field) {
  const std::uint32_t length = u32(field);
  need(length, field);
  if (length == 0) return {};  // some writers leave out the NUL of an empty string
  if (data_[pos_ + length - 1] != 0)
    throw lrd::Error(fmt::format("CDR string '{}' at offset {} is not NUL-terminated", field, pos_));
  std::string s(reinterpret_cast<const char*>(data_ + pos_), length - 1);
  pos_ += length;
  return s;
}

std::size_t CdrReader::sequence_length(const char* field, std::size_t min_element_size) {
  const std::uint32_t n = u32(field);
  if (min_element_size > 0 && n > (size_ - pos_) / min_element_size)
    throw lrd::Error(fmt::format("CDR message of {} bytes ends inside '{}' ({} elements at offset {})", size_,
                                 field, n, pos_));
  return n;
}

CdrReader::Bytes CdrReader::byte_sequence(const char* field) {
  const std::size_t n = sequence_length(field, 1);
  const Bytes b{data_ + pos_, n};
  pos_ += n;
  return b;
}

void CdrReader::f64_array(const char* field, double* values, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) values[i] = f64(field);
}

}  // namespace lrd::rosbag2
