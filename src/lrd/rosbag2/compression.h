#pragma once
// The compressions of MCAP chunks: "zstd" (libzstd) and "lz4" (LZ4's frame format, liblz4), and
// "" for none.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lrd::rosbag2 {

enum class Compression { none, zstd, lz4 };

// The name in a chunk record; and back, throwing lrd::Error "unknown compression 'x'".
[[nodiscard]] const char* compression_name(Compression c);
[[nodiscard]] Compression compression_from_name(const std::string& name);

[[nodiscard]] std::vector<std::uint8_t> compress(Compression c, const std::vector<std::uint8_t>& bytes);
// Exactly `size` bytes, or lrd::Error naming the compression and what is wrong.
[[nodiscard]] std::vector<std::uint8_t> decompress(Compression c, const std::uint8_t* data, std::size_t n,
                                                   std::size_t size);

}  // namespace lrd::rosbag2
