#pragma once
// Timestamp association as in TUM's associate.py (offset 0): every candidate pair with
// |a - b| < max_dt (strictly) is sorted by (|a - b|, a, b) and taken greedily, each stamp at most once.
#include <cstddef>
#include <span>
#include <vector>

namespace lrd::eval {

struct Match {
  std::size_t first = 0;   // index into the first (ground-truth) stamps
  std::size_t second = 0;  // index into the second (estimated) stamps
};

// Both stamp lists must be sorted ascending without duplicates (as read_trajectory_tum returns them).
// The result is sorted by first stamp, like associate.py's final matches.sort().
[[nodiscard]] std::vector<Match> associate(std::span<const double> first, std::span<const double> second,
                                           double max_dt);

}  // namespace lrd::eval
