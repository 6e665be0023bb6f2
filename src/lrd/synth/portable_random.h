#pragma once
// Random draws that are bit-identical on every platform: built from the raw output of
// std::mt19937_64 (fully specified by the standard), never from the <random> distributions
// (whose algorithms each standard library chooses). Same seed, same synthetic sequence, anywhere.
#include <cstddef>
#include <cstdint>
#include <random>

namespace lrd::synth {

class PortableRandom {
 public:
  explicit PortableRandom(std::uint64_t seed) : rng_(seed) {}
  // Uniform in [a, b), 53 bits of resolution.
  double uniform(double a, double b) { return a + (b - a) * static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
  float uniform(float a, float b) { return a + (b - a) * static_cast<float>(rng_() >> 40) * 0x1.0p-24f; }
  // Uniform index in [0, n).
  std::size_t pick(std::size_t n) { return static_cast<std::size_t>(rng_() % n); }
  std::uint64_t bits() { return rng_(); }

 private:
  std::mt19937_64 rng_;
};

}  // namespace lrd::synth
