#pragma once
// A bag-of-words vocabulary for 256-bit ORB descriptors, our own replacement for DBoW2
// (Galvez-Lopez & Tardos 2012): a vocabulary tree (Nister & Stewenius 2006) whose leaves are
// the words, with an idf weight per word.
//
// Training clusters the descriptors hierarchically: at each node, k-medians in Hamming space
// (k-means++ seeding from a seeded std::mt19937_64 with our own draws, then Lloyd iterations
// whose centres are the bit-wise majority of their members), recursing until `levels` or until a
// node's descriptors are all equal. A node with at most k distinct descriptors gets one child per
// distinct descriptor. Same input and seed give a bit-identical file, whatever the thread count:
// the tree takes integer arithmetic and our own draws only (the same with every standard
// library); the idf weights take std::log.
//
// idf(word) = ln(N / n): N training images with descriptors, n of them containing the word
// (descriptors sent down the finished tree, as transform() does). A word no training image
// reaches (rare: the tree's descent can differ from the clustering) counts as seen once,
// ln(N): rarer than any seen word. A word in every image weighs 0 and is left out of BowVectors
// (a stop word). With a single training image every weight is 0.
//
// File (.lrdv), little-endian: "LRDVOC01", u32 version (1), u32 k, u32 levels, u32 node count,
// u32 word count, then per node in id order (parents before children, the root first):
// u32 parent (0xffffffff for the root), u32 word id (0xffffffff for an inner node), 32 descriptor
// bytes, f64 weight (idf for a word, 0 for an inner node). 48 bytes a node.
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "lrd/place/bow_vector.h"

namespace lrd::place {

struct VocabularyParams {
  int k = 10;               // branching factor, 2 .. 65536
  int levels = 5;           // depth of the tree below the root, 1 .. 32
  int max_iterations = 10;  // Lloyd iterations per node (>= 1)
  std::uint64_t seed = 0x5eed;
};

class Vocabulary {
 public:
  Vocabulary() = default;  // empty: no words

  // `descriptors`: one cv::Mat per training image, rows = descriptors, CV_8UC1, 32 columns (an
  // image without descriptors may be an empty Mat). Throws lrd::Error for invalid parameters,
  // a Mat of another type or width, or no descriptors at all. The nodes of one level are
  // clustered in parallel (TBB); the result does not depend on the thread count.
  static Vocabulary train(const std::vector<cv::Mat>& descriptors, const VocabularyParams& params);

  // Throws lrd::Error naming the file: missing or unreadable, not a vocabulary (bad magic),
  // unsupported version, truncated, or inconsistent (sizes, tree structure, word ids, weights).
  static Vocabulary load(const std::filesystem::path& file);
  // The same, loaded once per process and shared while anyone holds it (tests and benchmarks
  // build many systems on one vocabulary).
  static std::shared_ptr<const Vocabulary> load_shared(const std::filesystem::path& file);
  // Throws lrd::Error naming the file when it cannot be written, or when the vocabulary is empty.
  void save(const std::filesystem::path& file) const;
  // The vocabulary's identity: FNV-1a 64 of its .lrdv bytes (0 when empty). Map files record it,
  // because bag-of-words vectors from another vocabulary mean nothing.
  [[nodiscard]] std::uint64_t fingerprint() const;

  // Rows of `descriptors` (CV_8UC1, N x 32; may be empty) -> `bow`, the L1-normalised tf-idf
  // vector (tf = count / N; words of weight 0 left out), and `fv`, every row grouped under its
  // word's ancestor `levels_up` levels above the leaves (clamped to [0, levels - 1]: the node at
  // depth levels - levels_up below the root, or the leaf itself where the tree is shallower).
  // ORB-SLAM2 uses levels_up = 4 with 6 levels. An empty vocabulary gives empty outputs. Throws
  // lrd::Error for a Mat of another type or width.
  void transform(const cv::Mat& descriptors, BowVector& bow, FeatureVector& fv, int levels_up) const;
  void transform(const cv::Mat& descriptors, BowVector& bow) const;

  // DBoW2's L1 score of two L1-normalised vectors: 1 - 0.5 * sum |a_i - b_i| in [0, 1],
  // computed as the sum over the common words of (|a_i| + |b_i| - |a_i - b_i|) / 2.
  static double score(const BowVector& a, const BowVector& b);

  [[nodiscard]] bool empty() const { return word_nodes_.empty(); }
  [[nodiscard]] std::size_t word_count() const { return word_nodes_.size(); }
  [[nodiscard]] std::size_t node_count() const { return parents_.size(); }
  [[nodiscard]] int k() const { return k_; }
  [[nodiscard]] int levels() const { return levels_; }

  // The word of one 32-byte descriptor: down the tree, at each node to the nearest child (the
  // first on a tie). Throws lrd::Error on an empty vocabulary.
  [[nodiscard]] WordId word_of(const std::uint8_t* descriptor32) const;
  // The idf weight of word `w`. Throws lrd::Error when there is no such word.
  [[nodiscard]] double word_weight(WordId w) const;

  using Descriptor = std::array<std::uint64_t, 4>;  // 32 bytes as stored, compared by popcount

 private:
  [[nodiscard]] std::string serialize() const;  // the .lrdv bytes
  // The leaf reached from the root by `d`; `fv_node`, when not null, gets the node passed at
  // depth `fv_depth` (or the leaf, if shallower).
  [[nodiscard]] NodeId descend(const Descriptor& d, int fv_depth, NodeId* fv_node) const;
  // The work of both transform()s; `fv` may be null.
  void bow_of(const cv::Mat& descriptors, BowVector& bow, FeatureVector* fv, int levels_up) const;
  // Builds the child lists and word -> node from parents_ and node_words_, checking the tree
  // (parents first, at most k children, depth, leaves = words 0 .. word_count - 1). Returns the
  // problem, or "" when the tree is sound.
  [[nodiscard]] std::string index(std::size_t word_count);
  // idf of every word from the training images.
  void compute_weights(const std::vector<cv::Mat>& descriptors);

  int k_ = 0, levels_ = 0;
  // Per node, by id.
  std::vector<Descriptor> descriptors_;
  std::vector<NodeId> parents_;
  std::vector<WordId> node_words_;  // kNone for an inner node
  // Children of node n: children_[child_begin_[n] .. child_begin_[n + 1]).
  std::vector<std::uint32_t> child_begin_;
  std::vector<NodeId> children_;
  // Per word.
  std::vector<NodeId> word_nodes_;
  std::vector<double> word_weights_;
};

}  // namespace lrd::place
