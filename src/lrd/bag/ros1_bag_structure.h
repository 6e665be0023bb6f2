#pragma once
// The record structure of a ROS 1 bag (format 2.0), checked before rosbag_storage reads it.
// rosbag_storage trusts the lengths a bag states: a record header claiming 2 GB is allocated
// as such, a chunk's stated size is allocated before it is decompressed, an index position is
// followed wherever it points (found by fuzzing `lrdslam run --bag`). This walk reads only the
// records' lengths and headers, so a bag of any size is checked in one pass of seeks: every
// record lies inside the file, every header field inside its header, a chunk's size is bounded
// and an uncompressed chunk's size is its data's, the index position and every chunk position
// the index names are records of the file, and the index holds the connections and chunks the
// bag header counts.
#include <cstdint>
#include <filesystem>

namespace lrd::bag {

// A chunk larger than this uncompressed is refused (rosbag's default chunks are 768 KiB).
inline constexpr std::uint64_t kMaxRos1ChunkBytes = 256ull << 20;

// Throws lrd::Error "FILE: cannot read the bag: PROBLEM" when the structure is broken (or the file
// is no ROS 1 bag); a bag that passes may still hold messages its readers refuse.
void check_ros1_bag_structure(const std::filesystem::path& file);

}  // namespace lrd::bag
