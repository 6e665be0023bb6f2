#include "lrd/config/node_reader.h"

#include <algorithm>
#include <vector>

#include "lrd/util/error.h"

namespace lrd::config {
namespace {

template <class T>
constexpr const char* type_name() {
  if constexpr (std::is_same_v<T, bool>) return "a boolean (true/false)";
  if constexpr (std::is_same_v<T, int>) return "an integer";
  if constexpr (std::is_floating_point_v<T>) return "a number";
  if constexpr (std::is_same_v<T, std::string>) return "a string";
  if constexpr (std::is_same_v<T, std::vector<int>>) return "a list of integers";
  if constexpr (std::is_same_v<T, std::vector<double>>) return "a list of numbers";
  if constexpr (std::is_same_v<T, std::vector<std::string>>) return "a list of strings";
  return "a value of another type";
}

std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Scalar:
      return "'" + n.Scalar() + "'";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a mapping";
    default:
      return "nothing";
  }
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

}  // namespace

NodeReader::NodeReader() : node_(std::make_shared<const YAML::Node>(YAML::NodeType::Map)) {}

NodeReader::NodeReader(YAML::Node node, std::filesystem::path file, std::string prefix)
    : file_(std::move(file)), prefix_(std::move(prefix)) {
  // IsDefined() first: a missing key gives an invalid node that throws on anything else.
  if (!node.IsDefined() || node.IsNull()) {
    node_ = std::make_shared<const YAML::Node>(YAML::NodeType::Map);
    return;
  }
  node_ = std::make_shared<const YAML::Node>(node);
  if (!node.IsMap()) {
    fail(node, (prefix_.empty() ? std::string("the top level") : "section '" + prefix_ + "'") +
                   " must be a mapping of 'key: value', got " + describe(node));
  }
  // yaml-cpp keeps duplicate keys silently and lookups see only the first; reject them.
  std::set<std::string> seen;
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) fail(kv.first, "keys must be plain names");
    if (!seen.insert(kv.first.Scalar()).second)
      fail(kv.first, "duplicate key '" + full_key(kv.first.Scalar()) + "'");
  }
}

std::string NodeReader::full_key(const std::string& key) const {
  return prefix_.empty() ? key : prefix_ + "." + key;
}

void NodeReader::fail(const YAML::Node& at, const std::string& problem) const {
  const YAML::Mark mark = at.Mark();
  if (file_.empty()) throw Error(problem);
  if (mark.is_null()) throw file_error(file_, problem);
  throw line_error(file_, static_cast<std::size_t>(mark.line) + 1, problem);
}

YAML::Node NodeReader::lookup(const std::string& key) {
  known_.insert(key);
  const YAML::Node& map = *node_;  // const operator[] never inserts
  return map[key];
}

bool NodeReader::has(const std::string& key) const {
  known_.insert(key);
  const YAML::Node& map = *node_;
  return map[key].IsDefined();
}

template <class T>
T NodeReader::get(const std::string& key, const T& fallback) {
  const YAML::Node value = lookup(key);
  if (!value.IsDefined()) return fallback;
  try {
    if constexpr (std::is_same_v<T, std::filesystem::path>) {
      return std::filesystem::path(value.as<std::string>());
    } else {
      return value.as<T>();
    }
  } catch (const YAML::Exception&) {
    using Shown = std::conditional_t<std::is_same_v<T, std::filesystem::path>, std::string, T>;
    fail(value, "key '" + full_key(key) + "' must be " + type_name<Shown>() + ", got " + describe(value));
  }
}

template <class T>
T NodeReader::require(const std::string& key) {
  if (!has(key)) fail(*node_, "missing required key '" + full_key(key) + "'");
  return get<T>(key, T{});
}

NodeReader NodeReader::section(const std::string& key) {
  const YAML::Node value = lookup(key);
  return NodeReader(value, file_, full_key(key));
}

void NodeReader::check(bool ok, const std::string& key, const std::string& problem) const {
  if (ok) return;
  const YAML::Node& map = *node_;
  const YAML::Node value = map[key];
  fail(value.IsDefined() ? value : map, "key '" + full_key(key) + "' " + problem);
}

void NodeReader::finish() const {
  for (const auto& kv : *node_) {
    const std::string& key = kv.first.Scalar();
    if (known_.count(key) != 0) continue;
    std::string problem = (prefix_.empty() ? "unknown section '" : "unknown key '") + full_key(key) + "'";
    // Suggest the closest known key for typos.
    const std::string* best = nullptr;
    std::size_t best_d = 3;
    for (const std::string& k : known_) {
      const std::size_t d = edit_distance(key, k);
      if (d < best_d) best_d = d, best = &k;
    }
    if (best != nullptr) problem += " (did you mean '" + *best + "'?)";
    fail(kv.first, problem);
  }
}

#define LRD_NODE_READER_TYPE(T)                                \
  template T NodeReader::get<T>(const std::string&, const T&); \
  template T NodeReader::require<T>(const std::string&);
LRD_NODE_READER_TYPE(bool)
LRD_NODE_READER_TYPE(int)
LRD_NODE_READER_TYPE(float)
LRD_NODE_READER_TYPE(double)
LRD_NODE_READER_TYPE(std::string)
LRD_NODE_READER_TYPE(std::filesystem::path)
LRD_NODE_READER_TYPE(std::vector<int>)
LRD_NODE_READER_TYPE(std::vector<double>)
LRD_NODE_READER_TYPE(std::vector<std::string>)
#undef LRD_NODE_READER_TYPE

}  // namespace lrd::config
