#pragma once
// The .lrdv file layout (internal to place/vocabulary*.cc): a header (magic, version, k, levels,
// node and word counts) and one fixed-size record per node (parent, word, descriptor, weight),
// little-endian whatever the host.
#include <cstdint>
#include <cstring>
#include <string>

#include "lrd/place/vocabulary.h"
#include "lrd/util/binary_io.h"

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

using util::get_u32;
using util::get_u64;
using util::put_u32;
using util::put_u64;

}  // namespace lrd::place::vocabulary_format
