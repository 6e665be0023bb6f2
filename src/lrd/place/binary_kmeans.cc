#include "lrd/place/binary_kmeans.h"

#include <algorithm>
#include <array>
#include <random>

#include "lrd/place/vocabulary_format.h"

namespace lrd::place {

namespace {

using namespace vocabulary_format;

// Uniform in [0, 1) from the top 53 bits: the same on every standard library (unlike
// std::uniform_real_distribution, whose algorithm is unspecified).
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Lane j (bits 8j .. 8j+7) of kLanes[b] holds bit j of b: adding kLanes[byte] to a uint64 counts
// eight bits at once, up to 255 additions before a lane overflows.
constexpr std::array<std::uint64_t, 256> make_lanes() {
  std::array<std::uint64_t, 256> t{};
  for (int b = 0; b < 256; ++b)
    for (int j = 0; j < 8; ++j)
      if ((b >> j) & 1) t[b] |= std::uint64_t{1} << (8 * j);
  return t;
}
constexpr std::array<std::uint64_t, 256> kLanes = make_lanes();

// Bit-wise majority of each cluster (ties -> 0); an empty cluster keeps its centre.
void update_centres(const std::vector<Descriptor>& all, const std::vector<std::uint32_t>& members,
                    const std::vector<std::uint32_t>& assign, std::vector<Descriptor>& centres) {
  const std::size_t k = centres.size();
  std::vector<std::uint64_t> acc(k * 32, 0);
  std::vector<std::uint32_t> counts(k * 256, 0), pending(k, 0), sizes(k, 0);
  const auto flush = [&](std::size_t c) {
    for (int b = 0; b < 32; ++b) {
      std::uint64_t& a = acc[c * 32 + b];
      for (int j = 0; j < 8; ++j)
        counts[c * 256 + b * 8 + j] += static_cast<std::uint32_t>((a >> (8 * j)) & 0xff);
      a = 0;
    }
    pending[c] = 0;
  };
  for (std::size_t i = 0; i < members.size(); ++i) {
    const std::uint32_t c = assign[i];
    const std::uint8_t* bytes = bytes_of(all[members[i]]);
    std::uint64_t* a = &acc[c * 32];
    for (int b = 0; b < 32; ++b) a[b] += kLanes[bytes[b]];
    ++sizes[c];
    if (++pending[c] == 255) flush(c);
  }
  for (std::size_t c = 0; c < k; ++c) {
    if (sizes[c] == 0) continue;
    flush(c);
    std::uint8_t bytes[32] = {};
    for (int b = 0; b < 32; ++b)
      for (int j = 0; j < 8; ++j)
        if (2 * counts[c * 256 + b * 8 + j] > sizes[c]) bytes[b] |= static_cast<std::uint8_t>(1u << j);
    centres[c] = descriptor_at(bytes);
  }
}

// Nearest centre of each member (the first on a tie); true when any assignment changed.
bool assign_members(const std::vector<Descriptor>& all, const std::vector<std::uint32_t>& members,
                    const std::vector<Descriptor>& centres, std::vector<std::uint32_t>& assign) {
  bool changed = false;
  for (std::size_t i = 0; i < members.size(); ++i) {
    const Descriptor& d = all[members[i]];
    std::uint32_t best = 0;
    int best_d = distance(d, centres[0]);
    for (std::uint32_t c = 1; c < centres.size(); ++c) {
      const int dc = distance(d, centres[c]);
      if (dc < best_d) best_d = dc, best = c;
    }
    changed |= assign[i] != best;
    assign[i] = best;
  }
  return changed;
}

// k-means++ seeding (Arthur & Vassilvitskii 2007, D^2 weighting): the first centre uniformly,
// each next one with probability proportional to its squared distance to the nearest centre.
// Stops early when every member equals a centre (fewer than k distinct descriptors).
std::vector<Descriptor> seed_centres(const std::vector<Descriptor>& all,
                                     const std::vector<std::uint32_t>& members, int k, std::mt19937_64& rng) {
  const std::size_t n = members.size();
  std::vector<Descriptor> centres;
  std::size_t first = static_cast<std::size_t>(uniform01(rng) * static_cast<double>(n));
  centres.push_back(all[members[std::min(first, n - 1)]]);
  std::vector<std::uint64_t> d2(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto d = static_cast<std::uint64_t>(distance(all[members[i]], centres[0]));
    d2[i] = d * d;
  }
  while (centres.size() < static_cast<std::size_t>(k)) {
    std::uint64_t total = 0;
    for (std::uint64_t v : d2) total += v;  // at most n * 65536: exact as a double too
    if (total == 0) break;
    const auto r =
        std::min(static_cast<std::uint64_t>(uniform01(rng) * static_cast<double>(total)), total - 1);
    std::uint64_t cum = 0;
    std::size_t pick = 0;
    for (; pick < n; ++pick) {
      cum += d2[pick];
      if (cum > r) break;
    }
    centres.push_back(all[members[pick]]);
    for (std::size_t i = 0; i < n; ++i) {
      const auto d = static_cast<std::uint64_t>(distance(all[members[i]], centres.back()));
      d2[i] = std::min(d2[i], d * d);
    }
  }
  return centres;
}

}  // namespace

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

Clusters cluster(const std::vector<Descriptor>& all, const std::vector<std::uint32_t>& members,
                 const VocabularyParams& params, std::uint64_t seed) {
  Clusters out;
  std::vector<std::uint32_t> assign(members.size(), 0);
  if (members.size() <= static_cast<std::size_t>(params.k)) {
    for (std::size_t i = 0; i < members.size(); ++i) {
      const Descriptor& d = all[members[i]];
      const auto it = std::find(out.centres.begin(), out.centres.end(), d);
      assign[i] = static_cast<std::uint32_t>(it - out.centres.begin());
      if (it == out.centres.end()) out.centres.push_back(d);
    }
  } else {
    std::mt19937_64 rng(seed);
    out.centres = seed_centres(all, members, params.k, rng);
    assign_members(all, members, out.centres, assign);
    bool changed = true;
    for (int it = 0; it < params.max_iterations && changed; ++it) {
      update_centres(all, members, assign, out.centres);
      changed = assign_members(all, members, out.centres, assign);
    }
    // Out of iterations while still moving: centres are made the medians of their final members.
    if (changed) update_centres(all, members, assign, out.centres);
  }
  out.members.resize(out.centres.size());
  for (std::size_t i = 0; i < members.size(); ++i) out.members[assign[i]].push_back(members[i]);
  std::size_t kept = 0;
  for (std::size_t c = 0; c < out.centres.size(); ++c) {
    if (out.members[c].empty()) continue;
    if (kept != c) {  // a vector moved onto itself would be emptied
      out.centres[kept] = out.centres[c];
      out.members[kept] = std::move(out.members[c]);
    }
    ++kept;
  }
  out.centres.resize(kept);
  out.members.resize(kept);
  return out;
}

bool all_equal(const std::vector<Descriptor>& all, const std::vector<std::uint32_t>& members) {
  for (std::uint32_t m : members)
    if (all[m] != all[members.front()]) return false;
  return true;
}

}  // namespace lrd::place
