#pragma once
// k-medians clustering of binary (ORB) descriptors under the Hamming distance: how a vocabulary's
// tree is grown, one node's descriptors split into k children at a time (DBoW2's hierarchical
// k-means with bit-wise majority centres, as Gálvez-López and Tardós; k-means++ seeding). Every
// step is deterministic for a seed, on every standard library.
#include <bit>
#include <cstdint>
#include <vector>

#include "lrd/place/vocabulary.h"

namespace lrd::place {

using Descriptor = Vocabulary::Descriptor;

inline int distance(const Descriptor& a, const Descriptor& b) {
  return std::popcount(a[0] ^ b[0]) + std::popcount(a[1] ^ b[1]) + std::popcount(a[2] ^ b[2]) +
         std::popcount(a[3] ^ b[3]);
}

// SplitMix64's finaliser: independent seeds for each node from one seed and the node's id.
std::uint64_t splitmix64(std::uint64_t x);

struct Clusters {
  std::vector<Descriptor> centres;
  std::vector<std::vector<std::uint32_t>> members;  // indices into the training set, increasing
};

// One node's split: at most k distinct descriptors -> one cluster each (in order of first
// appearance), else k-medians. Empty clusters are dropped.
Clusters cluster(const std::vector<Descriptor>& all, const std::vector<std::uint32_t>& members,
                 const VocabularyParams& params, std::uint64_t seed);

// Whether the descriptors `members` of `all` are all the same (a node that cannot be split).
bool all_equal(const std::vector<Descriptor>& all, const std::vector<std::uint32_t>& members);

}  // namespace lrd::place
