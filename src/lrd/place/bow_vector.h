#pragma once
// The two views of an image that a bag-of-words vocabulary gives (after DBoW2, Galvez-Lopez &
// Tardos 2012): the weighted words it contains, for scoring places, and its descriptors grouped
// by vocabulary node, so that matching only compares descriptors under the same node.
#include <cstdint>
#include <map>
#include <vector>

namespace lrd::place {

using WordId = std::uint32_t;  // a leaf of the vocabulary tree, 0 .. word_count() - 1
using NodeId = std::uint32_t;  // any node of the tree, the root is 0

// Word -> tf-idf weight, L1-normalised (the sum of |w| is 1). A std::map so that iteration is
// ordered and deterministic.
using BowVector = std::map<WordId, double>;

// Node (at a chosen level above the leaves) -> indices of the descriptors (rows) under it, in
// increasing order (DBoW2's direct index).
using FeatureVector = std::map<NodeId, std::vector<std::uint32_t>>;

}  // namespace lrd::place
