#include "lrd/sweep/sweep_plan.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>

#include "lrd/config/config.h"
#include "lrd/dynamic/dynamic_params.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/synth/presets.h"
#include "lrd/system_params.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A bag `lrdslam run --bag` may read: a ROS 1 .bag, a ROS 2 .mcap or .db3, or a rosbag2 folder.
bool is_bag(const fs::path& p) {
  const std::string ext = p.extension().string();
  return ext == ".bag" || ext == ".mcap" || ext == ".db3" || fs::exists(p / "metadata.yaml");
}

// The `--sequence`/`--bag` arguments of an input, checked before anything runs.
std::vector<std::string> input_args(const fs::path& input) {
  std::error_code ec;
  if (!fs::exists(input, ec)) throw file_error(input, "no such sequence folder or bag");
  const fs::path absolute = fs::absolute(input).lexically_normal();
  if (is_bag(input)) return {"--bag", absolute.string()};
  if (!fs::is_directory(input, ec))
    throw file_error(input, "not a sequence folder or a bag (.bag, .mcap, .db3)");
  (void)io::TumSequence::open(input);  // throws naming the folder: no rgb.txt/associations.txt, ...
  return {"--sequence", absolute.string()};
}

std::string input_label(const fs::path& input) {
  fs::path p = fs::absolute(input).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return is_bag(input) && p.has_extension() ? p.stem().string() : p.filename().string();
}

// --set KEY=VALUE into a config's YAML: tracking.keyframe_close_tracked=50.
void apply_set(YAML::Node& root, const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == assignment.size())
    throw Error("sweep: --set " + assignment +
                ": expected KEY=VALUE (e.g. tracking.keyframe_close_tracked=50)");
  const std::string key = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw Error(fmt::format("sweep: --set {}: {}", assignment, e.msg));
  }
  std::vector<YAML::Node> path{root};
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (part.empty()) throw Error(fmt::format("sweep: --set {}: empty key part", assignment));
    if (dot == std::string::npos) {
      path.back()[part] = value;
      return;
    }
    YAML::Node next = path.back()[part];
    if (!next.IsDefined() || next.IsNull()) path.back()[part] = YAML::Node(YAML::NodeType::Map);
    path.push_back(path.back()[part]);
    start = dot + 1;
  }
}

// The YAML a variant's cells run with: its file (camera.settings made absolute, as the copy lives
// elsewhere) with every --set applied; checked by reading it as a run would.
std::string variant_config(const fs::path& file, const std::vector<std::string>& sets) {
  YAML::Node root(YAML::NodeType::Map);
  if (!file.empty()) {
    (void)config::load_config(file);  // the file's own errors, named by file:line
    root = YAML::LoadFile(file.string());
    YAML::Node camera = root["camera"];
    if (camera.IsMap() && camera["settings"].IsScalar() &&
        fs::path(camera["settings"].as<std::string>()).is_relative())
      camera["settings"] = (fs::absolute(file).parent_path() / camera["settings"].as<std::string>()).string();
  }
  for (const std::string& s : sets) apply_set(root, s);
  if (file.empty() && sets.empty()) return "";
  YAML::Emitter out;
  out << root;
  const std::string text = std::string(out.c_str()) + "\n";
  const std::string origin = file.empty() ? std::string("sweep --set") : file.string() + " with --set";
  (void)SystemParams::from_config(config::load_config_text(text, origin));  // unknown keys, bad values
  return text;
}

std::string cell_id(const std::string& sequence, const std::string& mode, const std::string& variant,
                    int repeat) {
  std::string id = fmt::format("{}__{}__{}__r{}", sequence, mode, variant, repeat);
  for (char& c : id)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == '@'))
      c = '_';
  return id;
}

struct Input {
  std::string label;
  std::vector<std::string> args;
};

std::vector<Input> inputs_of(const SweepSpec& spec) {
  std::vector<Input> inputs;
  for (const fs::path& s : spec.sequences) inputs.push_back({input_label(s), input_args(s)});
  for (const std::string& p : spec.presets) {
    (void)synth::find_preset(p);  // throws listing the valid names
    for (int seed : spec.seeds) {
      Input in;
      in.label = p + (spec.seeds.size() > 1 || seed != 1 ? fmt::format("@{}", seed) : "") +
                 (spec.realism != "clean" ? fmt::format(".{}", spec.realism) : "");
      in.args = {"--synth", p, "--seed", std::to_string(seed)};
      if (spec.frames > 0) in.args.insert(in.args.end(), {"--frames", std::to_string(spec.frames)});
      if (spec.realism != "clean") in.args.insert(in.args.end(), {"--realism", spec.realism});
      inputs.push_back(in);
    }
  }
  return inputs;
}

}  // namespace

std::string content_hash(const std::string& bytes) {
  return fmt::format("{:016x}", util::fnv1a64(bytes));
}

SweepPlan plan_sweep(const SweepSpec& spec) {
  if (spec.sequences.empty() && spec.presets.empty())
    throw Error("sweep: no inputs: give --sequences A,B (folders or bags) and/or --presets p,q");
  if (spec.modes.empty()) throw Error("sweep: no modes: give --modes (static, semantic, geometric, full)");
  if (spec.repeats < 1) throw Error("sweep: --repeats must be at least 1");
  if (spec.realism != "clean" && spec.realism != "tum")
    throw Error(fmt::format("sweep: --realism must be clean or tum, got '{}'", spec.realism));
  for (const std::string& m : spec.modes) (void)dynamic::parse_mode(m);  // throws naming the modes
  SweepPlan plan;
  plan.spec = spec;
  std::map<std::string, fs::path> variants = spec.variants;
  if (variants.empty()) variants["default"] = fs::path{};
  for (const auto& [name, file] : variants) plan.configs[name] = variant_config(file, spec.sets);
  for (const Input& in : inputs_of(spec)) {
    for (const std::string& mode : spec.modes) {
      for (const auto& [variant, file] : variants) {
        for (int r = 0; r < spec.repeats; ++r) {
          SweepCell c;
          c.index = static_cast<int>(plan.cells.size());
          c.sequence = in.label;
          c.mode = mode;
          c.variant = variant;
          c.repeat = r;
          c.id = cell_id(in.label, mode, variant, r);
          c.args = in.args;
          c.args.insert(c.args.end(), {"--mode", mode, "--yardstick", "--quiet"});
          if (!spec.segmenter.empty()) c.args.insert(c.args.end(), {"--segmenter", spec.segmenter});
          if (spec.deterministic) c.args.push_back("--deterministic");
          if (!plan.configs[variant].empty())
            c.args.insert(c.args.end(), {"--config", fmt::format("configs/{}.yaml", variant)});
          c.args.insert(c.args.end(), spec.run_args.begin(), spec.run_args.end());
          plan.cells.push_back(c);
        }
      }
    }
  }
  for (std::size_t i = 1; i < plan.cells.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (plan.cells[i].id == plan.cells[j].id)
        throw Error(
            fmt::format("sweep: two inputs are both named '{}' (rename one)", plan.cells[i].sequence));
  return plan;
}

json cell_json(const SweepCell& c) {
  return {{"index", c.index},     {"id", c.id},         {"sequence", c.sequence}, {"mode", c.mode},
          {"variant", c.variant}, {"repeat", c.repeat}, {"args", c.args}};
}

void write_manifest(const fs::path& dir, const SweepPlan& plan) {
  json cells = json::array();
  for (const SweepCell& c : plan.cells) cells.push_back(cell_json(c));
  const fs::path file = dir / "manifest.json";
  std::error_code ec;
  if (fs::exists(file, ec)) {
    const std::vector<SweepCell> existing = read_manifest(dir);
    const bool same =
        existing.size() == plan.cells.size() &&
        std::equal(existing.begin(), existing.end(), plan.cells.begin(),
                   [](const SweepCell& a, const SweepCell& b) { return a.id == b.id && a.args == b.args; });
    if (!same)
      throw file_error(file,
                       fmt::format("describes another sweep ({} cells; this one has {}): resume it with the "
                                   "same arguments, or give another --out",
                                   existing.size(), plan.cells.size()));
    return;
  }
  fs::create_directories(dir / "configs", ec);
  if (ec) throw file_error(dir, "cannot create the sweep folder: " + ec.message());
  for (const auto& [variant, text] : plan.configs)
    if (!text.empty()) util::write_file_bytes(dir / "configs" / (variant + ".yaml"), text);
  const json manifest = {{"format", "lrdslam-sweep/1"}, {"cells", cells}};
  util::write_file_bytes(file, manifest.dump(1) + "\n");
}

std::vector<SweepCell> read_manifest(const fs::path& dir) {
  const fs::path file = dir / "manifest.json";
  const std::string text = util::read_file_bytes(file, "sweep manifest");
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw file_error(file, std::string("not a sweep manifest: ") + e.what());
  }
  if (!j.is_object() || j.value("format", "") != "lrdslam-sweep/1" || !j["cells"].is_array())
    throw file_error(file, "not a sweep manifest (format lrdslam-sweep/1 with a cells list)");
  std::vector<SweepCell> cells;
  try {
    for (const json& c : j["cells"]) {
      SweepCell cell;
      cell.index = c.at("index").get<int>();
      cell.id = c.at("id").get<std::string>();
      cell.sequence = c.at("sequence").get<std::string>();
      cell.mode = c.at("mode").get<std::string>();
      cell.variant = c.at("variant").get<std::string>();
      cell.repeat = c.at("repeat").get<int>();
      cell.args = c.at("args").get<std::vector<std::string>>();
      if (cell.index != static_cast<int>(cells.size())) throw file_error(file, "cells out of order");
      cells.push_back(cell);
    }
  } catch (const json::exception& e) {
    throw file_error(file, std::string("a malformed cell: ") + e.what());
  }
  return cells;
}

}  // namespace lrd::sweep
