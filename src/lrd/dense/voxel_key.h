#pragma once
// One 64-bit hash key for an integer cell (x, y, z): 21 bits per axis, offset so that cells from
// -2^20 to 2^20 - 1 pack without collision (+-10 km at 1 cm cells). The voxel grid and the map
// evaluator's point grid share it.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>

namespace lrd::dense {

[[nodiscard]] inline std::uint64_t voxel_key(std::int64_t x, std::int64_t y, std::int64_t z) {
  const auto k = [](std::int64_t v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1FFFFF; };
  return k(x) | (k(y) << 21) | (k(z) << 42);
}

// The key of the cell of size 1 / inv_size holding p (p finite).
[[nodiscard]] inline std::uint64_t voxel_key(const Eigen::Vector3f& p, double inv_size) {
  const auto cell = [&](float v) { return static_cast<std::int64_t>(std::floor(v * inv_size)); };
  return voxel_key(cell(p.x()), cell(p.y()), cell(p.z()));
}

}  // namespace lrd::dense
