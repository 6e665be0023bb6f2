#include "ros_args.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <vector>

#include "lrd/util/error.h"

namespace lrd_ros2 {

namespace {

std::pair<std::string, std::string> split_assignment(const std::string& flag, const std::string& text) {
  const std::size_t at = text.find(":=");
  if (at == std::string::npos || at == 0)
    throw lrd::Error(fmt::format("--ros-args {} '{}': expected NAME:=VALUE", flag, text));
  return {text.substr(0, at), text.substr(at + 2)};
}

std::string absolute_key(const std::string& key) {
  return !key.empty() && key[0] == '/' ? key : fmt::format("/{}", key);
}

// A map under ros__parameters -> name.with.dots = scalar (or a YAML sequence, kept as written).
void flatten(const YAML::Node& node, const std::string& prefix, const std::string& key,
             const std::string& file, std::vector<RosArgs::Param>& out) {
  for (const auto& entry : node) {
    const std::string key_name = entry.first.as<std::string>();
    const std::string name = prefix.empty() ? key_name : fmt::format("{}.{}", prefix, key_name);
    const std::string origin = fmt::format("{}:{}", file, entry.second.Mark().line + 1);
    if (entry.second.IsMap()) {
      flatten(entry.second, name, key, file, out);
    } else {
      YAML::Emitter e;
      e << entry.second;
      out.push_back({key, name, e.c_str(), origin});
    }
  }
}

// Node keys down to ros__parameters: "lrdslam", "/**", or nested "robot1: {lrdslam: ...}".
void read_node_keys(const YAML::Node& node, const std::string& path, const std::string& file,
                    std::vector<RosArgs::Param>& out) {
  if (!node.IsMap())
    throw lrd::Error(
        fmt::format("{}:{}: expected a node name and ros__parameters", file, node.Mark().line + 1));
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    if (key == "ros__parameters") {
      if (!entry.second.IsMap())
        throw lrd::Error(
            fmt::format("{}:{}: ros__parameters is not a map", file, entry.second.Mark().line + 1));
      flatten(entry.second, "", path.empty() ? "/" : path, file, out);
    } else {
      read_node_keys(entry.second, path + absolute_key(key), file, out);
    }
  }
}

void read_params_file(const std::string& file, std::vector<RosArgs::Param>& out) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw lrd::Error(fmt::format("--params-file {}: cannot read the file", file));
  } catch (const YAML::Exception& e) {
    throw lrd::Error(fmt::format("--params-file {}:{}: {}", file, e.mark.line + 1, e.msg));
  }
  try {
    read_node_keys(root, "", file, out);
  } catch (const YAML::Exception& e) {
    throw lrd::Error(fmt::format("--params-file {}:{}: {}", file, e.mark.line + 1, e.msg));
  }
}

std::vector<std::string> name_tokens(const std::string& name) {
  std::vector<std::string> tokens;
  std::size_t from = 0;
  while (from <= name.size()) {
    const std::size_t at = std::min(name.find('/', from), name.size());
    if (at > from) tokens.push_back(name.substr(from, at - from));
    from = at + 1;
  }
  return tokens;
}

bool tokens_match(const std::vector<std::string>& key, std::size_t k, const std::vector<std::string>& fqn,
                  std::size_t f) {
  if (k == key.size()) return f == fqn.size();
  if (key[k] == "**")  // any number of name tokens, none included
    return tokens_match(key, k + 1, fqn, f) || (f < fqn.size() && tokens_match(key, k, fqn, f + 1));
  return f < fqn.size() && (key[k] == "*" || key[k] == fqn[f]) && tokens_match(key, k + 1, fqn, f + 1);
}

// rcl's node-key wildcards: "/**" any number of name tokens, "/*" exactly one.
bool key_matches(const std::string& key, const std::string& fqn) {
  return tokens_match(name_tokens(key), 0, name_tokens(fqn), 0);
}

// A node name as rcl accepts one: a letter or '_', then letters, digits and '_'.
bool valid_node_name(const std::string& name) {
  if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0]))) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; });
}

// One argument inside --ros-args; i advances past what it consumes.
void parse_ros_arg(const std::vector<std::string>& argv, std::size_t& i, RosArgs& args) {
  const std::string& flag = argv[i];
  const auto value = [&]() -> const std::string& {
    if (i + 1 >= argv.size()) throw lrd::Error(fmt::format("--ros-args {} needs a value", flag));
    return argv[++i];
  };
  if (flag == "-r" || flag == "--remap") {
    auto [from, to] = split_assignment(flag, value());
    if (const std::size_t c = from.find(':'); c != std::string::npos) from = from.substr(c + 1);  // node:FROM
    if (from == "__node" || from == "__name")
      args.node_name = to;
    else if (from == "__ns")
      args.node_namespace = absolute_key(to);
    else
      args.remaps[from] = to;
  } else if (flag == "-p" || flag == "--param") {
    auto [name, yaml] = split_assignment(flag, value());
    std::string key = "/**";
    if (const std::size_t c = name.find(':'); c != std::string::npos) {
      key = absolute_key(name.substr(0, c));
      name = name.substr(c + 1);
    }
    args.params.push_back({key, name, yaml, fmt::format("-p {}", name)});
  } else if (flag == "--params-file") {
    read_params_file(value(), args.params);
  } else if (flag == "--log-level" || flag == "-e" || flag == "--enclave" || flag == "--log-config-file") {
    (void)value();  // logging and security enclaves: not ours to change
  } else if (flag.rfind("--enable-", 0) == 0 || flag.rfind("--disable-", 0) == 0) {
  } else {
    throw lrd::Error(fmt::format("--ros-args: unknown argument '{}'", flag));
  }
}

}  // namespace

RosArgs parse_ros_args(const std::vector<std::string>& argv) {
  RosArgs args;
  bool ros = false;
  for (std::size_t i = 0; i < argv.size(); ++i) {
    if (argv[i] == "--ros-args") {
      ros = true;
    } else if (argv[i] == "--") {
      ros = false;
    } else if (ros) {
      parse_ros_arg(argv, i, args);
    } else {
      args.other_args.push_back(argv[i]);
    }
  }
  if (!args.node_name.empty() && !valid_node_name(args.node_name))
    throw lrd::Error(fmt::format("--ros-args -r __node:={}: not a valid node name", args.node_name));
  return args;
}

ParamStore::ParamStore(const RosArgs& args, const std::string& node_fqn) {
  for (const RosArgs::Param& p : args.params)
    if (key_matches(p.node_key, node_fqn)) values_[p.name] = p;
}

const RosArgs::Param* ParamStore::find(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return nullptr;
  read_.insert(name);
  return &it->second;
}

namespace {

template <typename T>
void convert(const RosArgs::Param& p, const char* type, T& value) {
  try {
    const YAML::Node node = YAML::Load(p.yaml);
    if (!node.IsScalar()) throw YAML::Exception(YAML::Mark(), "not a scalar");
    value = node.as<T>();
  } catch (const YAML::Exception&) {
    throw lrd::Error(fmt::format("parameter {} ({}): '{}' is not {}", p.name, p.origin, p.yaml, type));
  }
}

}  // namespace

void ParamStore::get(const std::string& name, std::string& value) const {
  if (const RosArgs::Param* p = find(name)) convert(*p, "a string", value);
}
void ParamStore::get(const std::string& name, bool& value) const {
  if (const RosArgs::Param* p = find(name)) convert(*p, "a bool", value);
}
void ParamStore::get(const std::string& name, int& value) const {
  if (const RosArgs::Param* p = find(name)) convert(*p, "an integer", value);
}
void ParamStore::get(const std::string& name, double& value) const {
  if (const RosArgs::Param* p = find(name)) convert(*p, "a number", value);
}

std::vector<std::string> ParamStore::unused() const {
  std::vector<std::string> names;
  for (const auto& [name, p] : values_)
    if (read_.count(name) == 0) names.push_back(fmt::format("{} ({})", name, p.origin));
  return names;
}

}  // namespace lrd_ros2
