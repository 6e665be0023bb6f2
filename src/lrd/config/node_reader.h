#pragma once
// Typed, checked access to one section of an lrd-slam YAML config. Each module reads its own
// section through a NodeReader: get<T>() for every key it knows (with its default), then
// finish(), which rejects any key nobody asked for ("FILE:LINE: unknown key 'features.nfeaturs'").
// Every error is an lrd::Error naming the file, the line (from yaml-cpp's Mark) and the full key.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <memory>
#include <set>
#include <string>

namespace lrd::config {

class NodeReader {
 public:
  // An empty section: every get() returns its default. `prefix` is the dotted path of `node`
  // ("tracking", "dense.tsdf"), used in messages.
  NodeReader();
  NodeReader(YAML::Node node, std::filesystem::path file, std::string prefix);

  // Value of `key`, or `fallback` when the key is absent. Throws lrd::Error when the value does
  // not convert to T. Supported T: bool, int, float, double, std::string, std::filesystem::path,
  // std::vector<int>, std::vector<double>, std::vector<std::string>.
  template <class T>
  [[nodiscard]] T get(const std::string& key, const T& fallback);
  // Like get(), but the key must be present.
  template <class T>
  [[nodiscard]] T require(const std::string& key);

  // Nested mapping `key` as its own reader (absent: an empty one); the caller finishes it.
  [[nodiscard]] NodeReader section(const std::string& key);

  [[nodiscard]] bool has(const std::string& key) const;
  // Throws "FILE:LINE: key 'prefix.key' <problem>" unless ok; for range checks after get().
  void check(bool ok, const std::string& key, const std::string& problem) const;
  // Throws for the first key of this section that no get()/require()/section()/has() asked for.
  void finish() const;

  [[nodiscard]] const std::filesystem::path& file() const { return file_; }
  [[nodiscard]] const std::string& prefix() const { return prefix_; }
  [[nodiscard]] const YAML::Node& node() const { return *node_; }
  // "prefix.key"
  [[nodiscard]] std::string full_key(const std::string& key) const;

 private:
  [[nodiscard]] YAML::Node lookup(const std::string& key);
  [[noreturn]] void fail(const YAML::Node& at, const std::string& problem) const;

  // Shared and never modified: assigning a YAML::Node writes through to the node it refers to,
  // so readers rebind a pointer instead.
  std::shared_ptr<const YAML::Node> node_;
  std::filesystem::path file_;
  std::string prefix_;
  mutable std::set<std::string> known_;  // keys asked for, i.e. keys this module understands
};

}  // namespace lrd::config
