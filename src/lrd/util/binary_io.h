#pragma once
// Little-endian binary records, whatever the host: appending to a byte string and reading back
// with bounds checks. Shared by the file formats (the vocabulary's .lrdv, the map's .lrdmap).
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include "lrd/util/atomic_file.h"
#include "lrd/util/error.h"

namespace lrd::util {

// One append per value (not a push_back per byte): a map save copies under the map mutex with these.
inline void put_u32(std::string& s, std::uint32_t v) {
  char bytes[4];
  for (int i = 0; i < 4; ++i) bytes[i] = static_cast<char>((v >> (8 * i)) & 0xff);
  s.append(bytes, 4);
}
inline void put_u64(std::string& s, std::uint64_t v) {
  char bytes[8];
  for (int i = 0; i < 8; ++i) bytes[i] = static_cast<char>((v >> (8 * i)) & 0xff);
  s.append(bytes, 8);
}
inline void put_i32(std::string& s, std::int32_t v) {
  put_u32(s, static_cast<std::uint32_t>(v));
}
inline void put_f32(std::string& s, float v) {
  put_u32(s, std::bit_cast<std::uint32_t>(v));
}
inline void put_f64(std::string& s, double v) {
  put_u64(s, std::bit_cast<std::uint64_t>(v));
}

inline std::uint32_t get_u32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
         std::uint32_t{p[3]} << 24;
}
inline std::uint64_t get_u64(const std::uint8_t* p) {
  return std::uint64_t{get_u32(p)} | std::uint64_t{get_u32(p + 4)} << 32;
}

// 64-bit FNV-1a: a checksum that catches any flipped or truncated byte of a file.
inline std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t hash = 0xcbf29ce484222325ull) {
  for (const char c : bytes) {
    hash ^= static_cast<std::uint8_t>(c);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

// Reads records from bytes in memory; running past the end throws "FILE: truncated <what>".
class ByteReader {
 public:
  ByteReader(std::string_view bytes, std::filesystem::path file) : bytes_(bytes), file_(std::move(file)) {}

  [[nodiscard]] std::size_t remaining() const { return bytes_.size() - pos_; }
  [[nodiscard]] std::size_t position() const { return pos_; }
  [[nodiscard]] const std::filesystem::path& file() const { return file_; }
  // The next n bytes, checked.
  std::string_view take(std::size_t n, const char* what) {
    if (n > remaining())
      throw file_error(file_, std::string("truncated ") + what + ": " + std::to_string(n) +
                                  " bytes needed at offset " + std::to_string(pos_) + ", " +
                                  std::to_string(remaining()) + " left");
    const std::string_view out = bytes_.substr(pos_, n);
    pos_ += n;
    return out;
  }
  std::uint32_t u32(const char* what) { return get_u32(data(take(4, what))); }
  std::uint64_t u64(const char* what) { return get_u64(data(take(8, what))); }
  std::int32_t i32(const char* what) { return static_cast<std::int32_t>(u32(what)); }
  float f32(const char* what) { return std::bit_cast<float>(u32(what)); }
  double f64(const char* what) { return std::bit_cast<double>(u64(what)); }

 private:
  static const std::uint8_t* data(std::string_view s) {
    return reinterpret_cast<const std::uint8_t*>(s.data());
  }

  std::string_view bytes_;
  std::size_t pos_ = 0;
  std::filesystem::path file_;
};

// The whole file; throws "FILE: <problem>" when it is missing or unreadable.
[[nodiscard]] std::string read_file_bytes(const std::filesystem::path& file, const std::string& kind);
// Writes the bytes through util::AtomicFile (a temporary beside FILE renamed over it: a crash or a
// full disk never leaves half a file); throws "FILE: <problem>".
void write_file_bytes(const std::filesystem::path& file, std::string_view bytes, Sync sync = Sync::yes);

}  // namespace lrd::util
