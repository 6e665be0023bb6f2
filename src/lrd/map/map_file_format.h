#pragma once
// The .lrdmap layout constants the writer (map_file.cc) and the reader (map_file_reader.cc) share.
#include <cstddef>
#include <cstdint>

namespace lrd::map::file_format {

inline constexpr char kMagic[8] = {'L', 'R', 'D', 'M', 'A', 'P', '0', '1'};
// Magic, version, section count, total size.
inline constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8;
// An id slot that names nothing (no map point, no parent, no reference keyframe).
inline constexpr std::uint64_t kNone = UINT64_MAX;

}  // namespace lrd::map::file_format
