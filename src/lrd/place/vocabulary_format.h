#pragma once
// The .lrdv file layout (internal to place/vocabulary*.cc): a header (magic, version, k, levels,
// node and word counts) and one fixed-size record per node (parent, word, descriptor, weight),
// little-endian whatever the host.
#include <cstdint>
#include <cstring>
#include <string>

#include "lrd/place/vocabulary.h"

namespace lrd::place::vocabulary_format {

using Descriptor = Vocabulary::Descriptor;

inline constexpr char kMagic[8] = {'L', 'R', 'D', 'V', 'O', 'C', '0', '1'};
inline constexpr std::uint32_t kVersion = 1;
inline constexpr std::uint32_t kNone = 0xffffffffu;
inline constexpr std::size_t kHeaderBytes = 8 + 5 * 4;
inline constexpr std::size_t kNodeBytes = 4 + 4 + 32 + 8;
// Sanity bounds, so that a corrupt header cannot ask for absurd work.
inline constexpr int kMaxK = 1 << 16;
inline constexpr int kMaxLevels = 32;

inline Descriptor descriptor_at(const std::uint8_t* p) {
  Descriptor d;
  std::memcpy(d.data(), p, 32);
  return d;
}

// Byte i of a descriptor as stored (the memcpy'd bytes, whatever the host's endianness).
inline const std::uint8_t* bytes_of(const Descriptor& d) {
  return reinterpret_cast<const std::uint8_t*>(d.data());
}

inline void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
inline void put_u64(std::string& s, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
inline std::uint32_t get_u32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
         std::uint32_t{p[3]} << 24;
}
inline std::uint64_t get_u64(const std::uint8_t* p) {
  return std::uint64_t{get_u32(p)} | std::uint64_t{get_u32(p + 4)} << 32;
}

}  // namespace lrd::place::vocabulary_format
