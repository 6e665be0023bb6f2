#pragma once
// Tables of N(0,1) and U[0,1) values for the sensor models, filled once from a seed: per-pixel
// hashing is several times slower, and the renderer must produce a 900-frame sequence in under a
// minute. A frame's stream reads the tables from an offset hashed from (seed, frame, stream), so
// the same (seed, frame, pixel, stream) always gets the same value: the static and the full render
// of a frame share their noise.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace lrd::synth {

class NoiseTable {
 public:
  explicit NoiseTable(std::uint64_t seed);

  // Value i of stream `stream` in frame `frame`.
  class Stream {
   public:
    Stream(const std::vector<float>& table, std::uint64_t seed, int frame, std::uint64_t stream);
    [[nodiscard]] float operator()(std::size_t i) const { return table_[(offset_ + i) & kMask]; }

   private:
    const std::vector<float>& table_;
    std::size_t offset_;
  };
  [[nodiscard]] Stream gaussian(int frame, std::uint64_t stream) const {
    return {gaussian_, seed_, frame, stream};
  }
  [[nodiscard]] Stream uniform(int frame, std::uint64_t stream) const {
    return {uniform_, seed_, frame, stream};
  }

  static constexpr std::size_t kBits = 22;
  static constexpr std::size_t kMask = (std::size_t{1} << kBits) - 1;

 private:
  std::uint64_t seed_;
  std::vector<float> gaussian_, uniform_;
};

}  // namespace lrd::synth
