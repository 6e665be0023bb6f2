#include "lrd/place/vocabulary.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <string>

#include "lrd/place/binary_kmeans.h"
#include "lrd/place/vocabulary_format.h"
#include "lrd/util/error.h"

namespace lrd::place {

namespace {

using Descriptor = Vocabulary::Descriptor;
using namespace vocabulary_format;

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
