#include "lrd/eval/association.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace lrd::eval {
namespace {

struct Candidate {
  double diff;
  std::size_t a;  // index into first
  std::size_t b;  // index into second
};

}  // namespace

std::vector<Match> associate(std::span<const double> first, std::span<const double> second, double max_dt) {
  // Sorted input: the candidates of stamp a lie in a window of second, found by binary search, instead
  // of associate.py's all-pairs loop. The window is twice as wide so rounding cannot drop a candidate;
  // the exact test on diff decides, as in associate.py.
  std::vector<Candidate> candidates;
  for (std::size_t a = 0; a < first.size(); ++a) {
    auto it = std::lower_bound(second.begin(), second.end(), first[a] - 2.0 * max_dt);
    for (; it != second.end() && *it <= first[a] + 2.0 * max_dt; ++it) {
      const double diff = std::abs(first[a] - *it);
      if (diff < max_dt) candidates.push_back({diff, a, static_cast<std::size_t>(it - second.begin())});
    }
  }
  // Stamps are sorted and unique, so ordering by index equals associate.py's ordering by stamp value.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.diff, x.a, x.b) < std::tie(y.diff, y.a, y.b);
  });
  std::vector<bool> first_used(first.size(), false);
  std::vector<bool> second_used(second.size(), false);
  std::vector<Match> matches;
  for (const Candidate& c : candidates) {
    if (first_used[c.a] || second_used[c.b]) continue;
    first_used[c.a] = true;
    second_used[c.b] = true;
    matches.push_back({c.a, c.b});
  }
  std::sort(matches.begin(), matches.end(), [](const Match& x, const Match& y) { return x.first < y.first; });
  return matches;
}

}  // namespace lrd::eval
