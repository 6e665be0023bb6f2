// Vocabulary::save and Vocabulary::load: the .lrdv file (place/vocabulary_format.h).
#include <bit>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>

#include "lrd/place/vocabulary.h"
#include "lrd/place/vocabulary_format.h"
#include "lrd/util/error.h"

namespace lrd::place {

using namespace vocabulary_format;

std::string Vocabulary::serialize() const {
  std::string buf;
  buf.reserve(kHeaderBytes + parents_.size() * kNodeBytes);
  buf.append(kMagic, sizeof kMagic);
  put_u32(buf, kVersion);
  put_u32(buf, static_cast<std::uint32_t>(k_));
  put_u32(buf, static_cast<std::uint32_t>(levels_));
  put_u32(buf, static_cast<std::uint32_t>(parents_.size()));
  put_u32(buf, static_cast<std::uint32_t>(word_nodes_.size()));
  for (std::size_t n = 0; n < parents_.size(); ++n) {
    put_u32(buf, parents_[n]);
    put_u32(buf, node_words_[n]);
    buf.append(reinterpret_cast<const char*>(bytes_of(descriptors_[n])), 32);
    put_u64(buf, std::bit_cast<std::uint64_t>(node_words_[n] == kNone ? 0.0 : word_weights_[node_words_[n]]));
  }
  return buf;
}

void Vocabulary::save(const std::filesystem::path& file) const {
  if (empty()) throw file_error(file, "cannot save an empty vocabulary");
  util::write_file_bytes(file, serialize());
}

std::uint64_t Vocabulary::fingerprint() const {
  return empty() ? 0 : util::fnv1a64(serialize());
}

Vocabulary Vocabulary::load(const std::filesystem::path& file) {
  // One read of the whole file, then parsing from memory.
  const std::string bytes = util::read_file_bytes(file, "vocabulary");
  const std::span<const std::uint8_t> buf(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  const std::size_t magic_bytes = std::min(buf.size(), sizeof kMagic);
  if (magic_bytes > 0 && std::memcmp(buf.data(), kMagic, magic_bytes) != 0)  // no data() when empty
    throw file_error(file, "not an lrd-slam vocabulary (bad magic, expected \"LRDVOC01\")");
  if (buf.size() < kHeaderBytes)
    throw file_error(
        file, "truncated vocabulary: " + std::to_string(buf.size()) + " bytes, shorter than the header");
  const std::uint8_t* p = buf.data() + sizeof kMagic;
  const std::uint32_t version = get_u32(p), k = get_u32(p + 4), levels = get_u32(p + 8);
  const std::uint32_t nodes = get_u32(p + 12), words = get_u32(p + 16);
  if (version != kVersion)
    throw file_error(file, "unsupported vocabulary version " + std::to_string(version) +
                               " (this build reads " + std::to_string(kVersion) + ")");
  if (k < 2 || k > static_cast<std::uint32_t>(kMaxK))
    throw file_error(file, "bad k = " + std::to_string(k) + " (must be 2 .. " + std::to_string(kMaxK) + ")");
  if (levels < 1 || levels > static_cast<std::uint32_t>(kMaxLevels))
    throw file_error(file, "bad levels = " + std::to_string(levels) + " (must be 1 .. " +
                               std::to_string(kMaxLevels) + ")");
  const std::uint64_t expected = kHeaderBytes + std::uint64_t{nodes} * kNodeBytes;
  if (buf.size() < expected)
    throw file_error(file, "truncated vocabulary: " + std::to_string(buf.size()) + " bytes, " +
                               std::to_string(expected) + " expected for " + std::to_string(nodes) +
                               " nodes");
  if (buf.size() > expected)
    throw file_error(file, std::to_string(buf.size() - expected) + " bytes after the last of " +
                               std::to_string(nodes) + " nodes");
  if (words >= nodes)
    throw file_error(file,
                     "bad word count " + std::to_string(words) + " for " + std::to_string(nodes) + " nodes");

  Vocabulary v;
  v.k_ = static_cast<int>(k);
  v.levels_ = static_cast<int>(levels);
  v.parents_.resize(nodes);
  v.node_words_.resize(nodes);
  v.descriptors_.resize(nodes);
  std::vector<double> weights(nodes);
  p = buf.data() + kHeaderBytes;
  for (std::uint32_t n = 0; n < nodes; ++n, p += kNodeBytes) {
    v.parents_[n] = get_u32(p);
    v.node_words_[n] = get_u32(p + 4);
    v.descriptors_[n] = descriptor_at(p + 8);
    weights[n] = std::bit_cast<double>(get_u64(p + 40));
    if (!std::isfinite(weights[n]) || weights[n] < 0.0)
      throw file_error(file, "node " + std::to_string(n) + " has a bad weight");
  }
  if (const std::string problem = v.index(words); !problem.empty()) throw file_error(file, problem);
  v.word_weights_.resize(words);
  for (std::uint32_t w = 0; w < words; ++w) v.word_weights_[w] = weights[v.word_nodes_[w]];
  return v;
}

std::shared_ptr<const Vocabulary> Vocabulary::load_shared(const std::filesystem::path& file) {
  static std::mutex mutex;
  static std::map<std::filesystem::path, std::weak_ptr<const Vocabulary>> cache;
  std::lock_guard lock(mutex);
  const std::filesystem::path key = std::filesystem::absolute(file).lexically_normal();
  if (auto v = cache[key].lock()) return v;
  auto v = std::make_shared<const Vocabulary>(load(file));
  cache[key] = v;
  return v;
}

}  // namespace lrd::place
