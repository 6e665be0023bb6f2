#pragma once
// ROS 2's serialisation of messages: CDR as XCDR1 little-endian (the 4-byte encapsulation header
// 00 01 00 00, then each primitive aligned to its size relative to the byte after the header;
// strings as a uint32 length counting a terminating NUL, sequences as a uint32 count). What
// rosbag2 stores and what a DDS node publishes, so the same code serves both.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace lrd::rosbag2 {

class CdrWriter {
 public:
  CdrWriter();  // writes the encapsulation header

  void u8(std::uint8_t v) { raw(&v, 1); }
  void boolean(bool v) { u8(v ? 1 : 0); }
  void u32(std::uint32_t v);
  void i32(std::int32_t v);
  void f64(double v);
  void string(std::string_view s);
  void sequence_length(std::size_t n);                             // before a sequence's elements
  void byte_sequence(const std::uint8_t* data, std::size_t size);  // uint8[]
  void f64_array(const double* values, std::size_t n);             // float64[N]: no length

  [[nodiscard]] std::vector<std::uint8_t> take() { return std::move(bytes_); }

 private:
  void align(std::size_t n);
  void raw(const void* data, std::size_t size);
  std::vector<std::uint8_t> bytes_;
};

// Reads one message; every read is checked against the end, so a short or malformed message is
// an lrd::Error naming the field ("CDR message of 40 bytes ends inside 'data' ..."), never a
// read past the buffer. Callers add where the message came from.
class CdrReader {
 public:
  // Throws lrd::Error for a buffer shorter than the header or an encapsulation other than
  // little-endian plain CDR.
  CdrReader(const std::uint8_t* data, std::size_t size);

  [[nodiscard]] std::uint8_t u8(const char* field);
  [[nodiscard]] bool boolean(const char* field) { return u8(field) != 0; }
  [[nodiscard]] std::uint32_t u32(const char* field);
  [[nodiscard]] std::int32_t i32(const char* field);
  [[nodiscard]] double f64(const char* field);
  [[nodiscard]] std::string string(const char* field);
  // A sequence's element count, checked against the bytes left at min_element_size each.
  [[nodiscard]] std::size_t sequence_length(const char* field, std::size_t min_element_size);
  // A uint8[] in place: a view into the buffer (valid while it lives).
  struct Bytes {
    const std::uint8_t* data;
    std::size_t size;
  };
  [[nodiscard]] Bytes byte_sequence(const char* field);
  void f64_array(const char* field, double* values, std::size_t n);

 private:
  void align(std::size_t n, const char* field);
  void need(std::size_t n, const char* field) const;
  const std::uint8_t* data_;
  std::size_t size_, pos_;  // pos_ counts from the buffer's start (the header included)
};

}  // namespace lrd::rosbag2
