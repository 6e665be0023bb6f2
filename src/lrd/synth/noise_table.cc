#include "lrd/synth/noise_table.h"

#include <cmath>

namespace lrd::synth {
namespace {

std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace

NoiseTable::Stream::Stream(const std::vector<float>& table, std::uint64_t seed, int frame,
                           std::uint64_t stream)
    : table_(table),
      offset_(splitmix(seed ^ splitmix(static_cast<std::uint64_t>(frame) * 0x100000001B3ull + stream)) &
              kMask) {}

NoiseTable::NoiseTable(std::uint64_t seed) : seed_(seed) {
  // Box-Muller for the normal values; both tables from one hash per pair of entries.
  gaussian_.resize(kMask + 1);
  uniform_.resize(kMask + 1);
  for (std::size_t i = 0; i <= kMask; i += 2) {
    const std::uint64_t h = splitmix(seed ^ (i * 0xD6E8FEB86659FD93ull));
    const double u1 = (static_cast<double>(h >> 40) + 1.0) * 0x1.0p-24,
                 u2 = static_cast<double>(h & 0xFFFFFF) * 0x1.0p-24;
    const double r = std::sqrt(-2.0 * std::log(u1));
    gaussian_[i] = static_cast<float>(r * std::cos(2.0 * M_PI * u2));
    gaussian_[i + 1] = static_cast<float>(r * std::sin(2.0 * M_PI * u2));
    const std::uint64_t g = splitmix(h);
    uniform_[i] = static_cast<float>(g >> 40) * 0x1.0p-24f;
    uniform_[i + 1] = static_cast<float>(g & 0xFFFFFF) * 0x1.0p-24f;
  }
}

}  // namespace lrd::synth
