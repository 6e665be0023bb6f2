#pragma once
// A ROS 2 node's command line as rcl reads it: everything between --ros-args and "--" (or the
// end; --ros-args may come again) is ROS's: -r/--remap FROM:=TO (with __node:= and __ns:=),
// -p/--param [node:]name:=value (the value read as YAML), --params-file FILE (ROS 2's layout:
// node key, then ros__parameters, nested maps joined with dots), --log-level and -e/--enclave
// (accepted). The rest is the program's. Parameters apply in command-line order, a later one
// overriding an earlier, each only where its node key (/**, /*, lrdslam, /ns/lrdslam) matches the
// node's fully qualified name.
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "lrd/node/node_params.h"

namespace lrd_ros2 {

struct RosArgs {
  std::string node_name;                      // __node:=, "" : the program's default
  std::string node_namespace;                 // __ns:=, "" : "/"
  std::map<std::string, std::string> remaps;  // topic FROM -> TO
  struct Param {
    std::string node_key;  // "/**" when none was given
    std::string name;
    std::string yaml;    // the value as written
    std::string origin;  // "-p", or "FILE:LINE"
  };
  std::vector<Param> params;            // in command-line order
  std::vector<std::string> other_args;  // the program's own
};

// Throws lrd::Error naming the argument (or FILE:LINE) for anything rcl would refuse.
[[nodiscard]] RosArgs parse_ros_args(const std::vector<std::string>& argv);

// The parameters that apply to one node, as lrd::node::ParamReader: a value of another type
// than asked for is an error naming it and where it was given.
class ParamStore final : public lrd::node::ParamReader {
 public:
  ParamStore(const RosArgs& args, const std::string& node_fqn);
  void get(const std::string& name, std::string& value) const override;
  void get(const std::string& name, bool& value) const override;
  void get(const std::string& name, int& value) const override;
  void get(const std::string& name, double& value) const override;
  // The parameters given but never read (no such parameter): for a warning.
  [[nodiscard]] std::vector<std::string> unused() const;

 private:
  const RosArgs::Param* find(const std::string& name) const;
  std::map<std::string, RosArgs::Param> values_;
  mutable std::set<std::string> read_;
};

}  // namespace lrd_ros2
