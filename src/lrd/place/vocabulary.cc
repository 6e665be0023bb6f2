#include "lrd/place/vocabulary.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <string>

#include "lrd/place/vocabulary_format.h"
#include "lrd/util/error.h"

namespace lrd::place {

namespace {

using Descriptor = Vocabulary::Descriptor;
using namespace vocabulary_format;

int distance(const Descriptor& a, const Descriptor& b) {
  return std::popcount(a[0] ^ b[0]) + std::popcount(a[1] ^ b[1]) + std::popcount(a[2] ^ b[2]) +
         std::popcount(a[3] ^ b[3]);
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

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

struct Clusters {
  std::vector<Descriptor> centres;
  std::vector<std::vector<std::uint32_t>> members;  // indices into the training set, increasing
};

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

// One node's split: at most k distinct descriptors -> one cluster each (in order of first
// appearance), else k-medians. Empty clusters are dropped.
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

void check_descriptors(const cv::Mat& d, const std::string& what) {
  if (d.empty()) return;
  if (d.type() != CV_8UC1 || d.cols != 32 || d.dims != 2)
    throw Error(what + ": descriptors must be CV_8UC1 with 32 columns (256-bit ORB), got type " +
                std::to_string(d.type()) + " with " + std::to_string(d.cols) + " columns");
}

}  // namespace

Vocabulary Vocabulary::train(const std::vector<cv::Mat>& descriptors, const VocabularyParams& params) {
  if (params.k < 2 || params.k > kMaxK)
    throw Error("vocabulary training: k = " + std::to_string(params.k) + " (must be 2 .. " +
                std::to_string(kMaxK) + ")");
  if (params.levels < 1 || params.levels > kMaxLevels)
    throw Error("vocabulary training: levels = " + std::to_string(params.levels) + " (must be 1 .. " +
                std::to_string(kMaxLevels) + ")");
  if (params.max_iterations < 1)
    throw Error("vocabulary training: max_iterations = " + std::to_string(params.max_iterations) +
                " (must be at least 1)");
  std::size_t total = 0;
  for (std::size_t i = 0; i < descriptors.size(); ++i) {
    check_descriptors(descriptors[i], "vocabulary training, image " + std::to_string(i));
    total += static_cast<std::size_t>(descriptors[i].rows);
  }
  if (total == 0) throw Error("vocabulary training: no descriptors");
  if (total >= kNone)
    throw Error("vocabulary training: too many descriptors (" + std::to_string(total) + ")");

  std::vector<Descriptor> all;
  all.reserve(total);
  for (const cv::Mat& d : descriptors)
    for (int r = 0; r < d.rows; ++r) all.push_back(descriptor_at(d.ptr<std::uint8_t>(r)));

  Vocabulary v;
  v.k_ = params.k;
  v.levels_ = params.levels;
  v.descriptors_.push_back(Descriptor{});  // the root matches nothing; its descriptor is unused
  v.parents_.push_back(kNone);

  // Breadth first, a level at a time: the nodes of a level are clustered in parallel, each with
  // its own generator seeded by its id, and numbered in a fixed order afterwards, so the tree
  // does not depend on scheduling.
  struct Pending {
    NodeId node;
    std::vector<std::uint32_t> members;
  };
  std::vector<Pending> frontier(1);
  frontier[0].node = 0;
  frontier[0].members.resize(total);
  for (std::size_t i = 0; i < total; ++i) frontier[0].members[i] = static_cast<std::uint32_t>(i);
  for (int depth = 0; depth < params.levels && !frontier.empty(); ++depth) {
    std::vector<Clusters> split(frontier.size());
    tbb::parallel_for(std::size_t{0}, frontier.size(), [&](std::size_t i) {
      split[i] =
          cluster(all, frontier[i].members, params, splitmix64(params.seed ^ splitmix64(frontier[i].node)));
    });
    std::vector<Pending> next;
    for (std::size_t i = 0; i < frontier.size(); ++i) {
      for (std::size_t c = 0; c < split[i].centres.size(); ++c) {
        const auto id = static_cast<NodeId>(v.parents_.size());
        v.descriptors_.push_back(split[i].centres[c]);
        v.parents_.push_back(frontier[i].node);
        // Children at depth `levels`, and nodes whose descriptors are all equal, are words.
        if (depth + 1 < params.levels && !all_equal(all, split[i].members[c]))
          next.push_back({id, std::move(split[i].members[c])});
      }
    }
    frontier = std::move(next);
    if (v.parents_.size() >= kNone) throw Error("vocabulary training: too many nodes");
  }

  // Words: the leaves, numbered in node order.
  std::vector<char> inner(v.parents_.size(), 0);
  for (std::size_t n = 1; n < v.parents_.size(); ++n) inner[v.parents_[n]] = 1;
  v.node_words_.assign(v.parents_.size(), kNone);
  WordId words = 0;
  for (std::size_t n = 0; n < v.parents_.size(); ++n)
    if (!inner[n]) v.node_words_[n] = words++;
  if (const std::string problem = v.index(words); !problem.empty())
    throw Error("vocabulary training: internal error: " + problem);
  v.compute_weights(descriptors);
  return v;
}

void Vocabulary::compute_weights(const std::vector<cv::Mat>& descriptors) {
  // The distinct words of each image (in parallel), then counted in image order.
  std::vector<std::vector<WordId>> seen(descriptors.size());
  tbb::parallel_for(std::size_t{0}, descriptors.size(), [&](std::size_t i) {
    const cv::Mat& d = descriptors[i];
    for (int r = 0; r < d.rows; ++r)
      seen[i].push_back(node_words_[descend(descriptor_at(d.ptr<std::uint8_t>(r)), 0, nullptr)]);
    std::sort(seen[i].begin(), seen[i].end());
    seen[i].erase(std::unique(seen[i].begin(), seen[i].end()), seen[i].end());
  });
  std::vector<std::uint32_t> images_with(word_nodes_.size(), 0);
  std::uint32_t images = 0;
  for (const auto& words : seen) {
    if (words.empty()) continue;  // an image without descriptors is no document
    ++images;
    for (WordId w : words) ++images_with[w];
  }
  word_weights_.resize(word_nodes_.size());
  for (std::size_t w = 0; w < word_nodes_.size(); ++w)
    word_weights_[w] =
        std::log(static_cast<double>(images) / static_cast<double>(std::max(images_with[w], 1u)));
}

std::string Vocabulary::index(std::size_t word_count) {
  const std::size_t n = parents_.size();
  if (n < 2) return "no words (" + std::to_string(n) + " nodes)";
  if (parents_[0] != kNone) return "the root (node 0) has a parent";
  std::vector<std::uint32_t> count(n + 1, 0);
  std::vector<int> depth(n, 0);
  for (std::size_t i = 1; i < n; ++i) {
    const NodeId p = parents_[i];
    if (p >= i)
      return "node " + std::to_string(i) + " has parent " + std::to_string(p) + " (parents come first)";
    if (++count[p] > static_cast<std::uint32_t>(k_))
      return "node " + std::to_string(p) + " has more than k children";
    depth[i] = depth[p] + 1;
    if (depth[i] > levels_) return "node " + std::to_string(i) + " is deeper than the levels";
  }
  child_begin_.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) child_begin_[i + 1] = child_begin_[i] + count[i];
  children_.assign(n - 1, 0);
  std::vector<std::uint32_t> fill(child_begin_.begin(), child_begin_.end() - 1);
  for (std::size_t i = 1; i < n; ++i) children_[fill[parents_[i]]++] = static_cast<NodeId>(i);

  word_nodes_.assign(word_count, kNone);
  for (std::size_t i = 0; i < n; ++i) {
    const bool leaf = count[i] == 0;
    const WordId w = node_words_[i];
    if (leaf != (w != kNone))
      return "node " + std::to_string(i) +
             (leaf ? " is a leaf without a word id" : " has children and a word id");
    if (!leaf) continue;
    if (w >= word_count || word_nodes_[w] != kNone)
      return "node " + std::to_string(i) + " has a bad or repeated word id " + std::to_string(w);
    word_nodes_[w] = static_cast<NodeId>(i);
  }
  for (std::size_t w = 0; w < word_count; ++w)
    if (word_nodes_[w] == kNone) return "word " + std::to_string(w) + " has no node";
  return {};
}

NodeId Vocabulary::descend(const Descriptor& d, int fv_depth, NodeId* fv_node) const {
  NodeId n = 0;
  int depth = 0;
  while (child_begin_[n] != child_begin_[n + 1]) {
    const std::uint32_t end = child_begin_[n + 1];
    NodeId best = children_[child_begin_[n]];
    int best_d = distance(d, descriptors_[best]);
    for (std::uint32_t c = child_begin_[n] + 1; c < end; ++c) {
      const int dc = distance(d, descriptors_[children_[c]]);
      if (dc < best_d) best_d = dc, best = children_[c];
    }
    n = best;
    if (++depth == fv_depth && fv_node != nullptr) *fv_node = n;
  }
  if (fv_node != nullptr && depth < fv_depth) *fv_node = n;  // a leaf above the chosen level
  return n;
}

WordId Vocabulary::word_of(const std::uint8_t* descriptor32) const {
  if (empty()) throw Error("Vocabulary::word_of: the vocabulary is empty");
  return node_words_[descend(descriptor_at(descriptor32), 0, nullptr)];
}

double Vocabulary::word_weight(WordId w) const {
  if (w >= word_weights_.size())
    throw Error("Vocabulary::word_weight: no word " + std::to_string(w) + " (" +
                std::to_string(word_count()) + " words)");
  return word_weights_[w];
}

void Vocabulary::transform(const cv::Mat& descriptors, BowVector& bow, FeatureVector& fv,
                           int levels_up) const {
  fv.clear();
  bow_of(descriptors, bow, &fv, levels_up);
}

void Vocabulary::transform(const cv::Mat& descriptors, BowVector& bow) const {
  bow_of(descriptors, bow, nullptr, 0);
}

void Vocabulary::bow_of(const cv::Mat& descriptors, BowVector& bow, FeatureVector* fv, int levels_up) const {
  bow.clear();
  check_descriptors(descriptors, "Vocabulary::transform");
  if (empty() || descriptors.empty()) return;
  const int fv_depth = fv != nullptr ? levels_ - std::clamp(levels_up, 0, levels_ - 1) : 0;
  for (int r = 0; r < descriptors.rows; ++r) {
    NodeId fv_node = 0;
    const NodeId leaf = descend(descriptor_at(descriptors.ptr<std::uint8_t>(r)), fv_depth, &fv_node);
    bow[node_words_[leaf]] += 1.0;
    if (fv != nullptr) (*fv)[fv_node].push_back(static_cast<std::uint32_t>(r));
  }
  // tf-idf (DBoW2's TF_IDF): count / N * idf; zero weights (stop words) are left out; then L1.
  double sum = 0.0;
  for (auto it = bow.begin(); it != bow.end();) {
    it->second = it->second / descriptors.rows * word_weights_[it->first];
    if (it->second > 0.0) {
      sum += it->second;
      ++it;
    } else {
      it = bow.erase(it);
    }
  }
  for (auto& [w, value] : bow) value /= sum;
}

double Vocabulary::score(const BowVector& a, const BowVector& b) {
  double s = 0.0;
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->first < ib->first) {
      ia = a.lower_bound(ib->first);
    } else if (ib->first < ia->first) {
      ib = b.lower_bound(ia->first);
    } else {
      s += std::abs(ia->second) + std::abs(ib->second) - std::abs(ia->second - ib->second);
      ++ia;
      ++ib;
    }
  }
  return 0.5 * s;
}

}  // namespace lrd::place
