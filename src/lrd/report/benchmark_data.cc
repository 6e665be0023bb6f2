#include "lrd/report/benchmark_data.h"

#include <algorithm>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "lrd/io/trajectory.h"
#include "lrd/report/run_data.h"
#include "lrd/report/sweep_data.h"
#include "lrd/report/trajectory_data.h"
#include "lrd/util/error.h"

namespace lrd::report {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Per mode and preset a few thousand points keep a page of 8 presets x 5 modes near a megabyte.
constexpr std::size_t kMaxPointsPerRun = 1500;

std::string string_field(const fs::path& file, const json& entry, const char* key) {
  if (!entry.is_object() || !entry.contains(key) || !entry[key].is_string())
    throw file_error(file, std::string("a run without a \"") + key + "\" string");
  return entry[key].get<std::string>();
}

// The names in the order the benchmark gave them ("presets"/"modes"), else as the runs list them.
json ordered_names(const json& results, const char* list_key, const char* run_key) {
  if (results.contains(list_key) && results[list_key].is_array()) return results[list_key];
  std::vector<std::string> names;
  for (const json& run : results["runs"]) {
    const std::string name = run[run_key].get<std::string>();
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

// The ground-truth file of the sequence a run read (its summary.json names it), when there is one.
std::optional<fs::path> run_ground_truth_file(const fs::path& run_dir) {
  // A run of a source without a folder (a bag, a rendered preset) left its ground truth beside it.
  if (fs::exists(run_dir / "groundtruth.txt")) return run_dir / "groundtruth.txt";
  if (!fs::exists(run_dir / "summary.json")) return std::nullopt;
  const json summary = read_json_file(run_dir / "summary.json");
  if (!summary.is_object() || !summary.contains("sequence") || !summary["sequence"].is_string())
    return std::nullopt;
  const fs::path gt = fs::path(summary["sequence"].get<std::string>()) / "groundtruth.txt";
  if (!fs::exists(gt)) return std::nullopt;
  return gt;
}

// Each sequence's ground truth read once, though every mode's run names it.
using GroundTruths = std::map<fs::path, io::Trajectory>;

// One mode's trajectory on its preset's plot: aligned positions and errors, or a note saying why
// there is none.
void add_trajectory(json& plot, const std::string& mode, const fs::path& run_dir, GroundTruths& truths) {
  const fs::path file = run_dir / "CameraTrajectory.txt";
  if (!fs::exists(file)) {
    plot["notes"].push_back(mode + ": no " + file.string());
    return;
  }
  const std::optional<fs::path> gt_file = run_ground_truth_file(run_dir);
  if (!gt_file) {
    plot["notes"].push_back(mode + ": no ground truth for " + run_dir.string());
    return;
  }
  auto gt = truths.find(*gt_file);
  if (gt == truths.end()) gt = truths.emplace(*gt_file, io::read_trajectory_tum(*gt_file)).first;
  const io::Trajectory est = io::read_trajectory_tum(file);
  try {
    json t = aligned_trajectory(gt->second, est, kMaxPointsPerRun);
    if (!plot.contains("gt_path")) plot["gt_path"] = t["gt_path"];
    t.erase("gt_path");
    t.erase("gt");
    plot["modes"][mode] = t;
  } catch (const Error& e) {  // fewer than two poses associate: the mode lost everything
    plot["notes"].push_back(mode + ": " + e.what());
  }
}

}  // namespace

bool is_benchmark_folder(const fs::path& dir) {
  return fs::exists(dir / "results.json") && !fs::exists(dir / "summary.json");
}

json collect_benchmark_data(const fs::path& bench_dir) {
  const fs::path file = bench_dir / "results.json";
  json results = read_json_file(file);
  // A sweep's results (lrdslam sweep collect): the same page, each cell the median of its repeats.
  if (is_sweep_results(results)) results = sweep_as_benchmark(results, file);
  if (!results.is_object() || !results.contains("runs") || !results["runs"].is_array())
    throw file_error(file, "not a benchmark's results (no \"runs\" list)");
  for (const json& run : results["runs"]) {
    (void)string_field(file, run, "preset");
    (void)string_field(file, run, "mode");
  }
  const fs::path dir = fs::absolute(bench_dir).lexically_normal();
  json data = {{"kind", "benchmark"},
               {"run", dir.filename().string()},
               {"run_dir", dir.string()},
               {"results", results},
               {"presets", ordered_names(results, "presets", "preset")},
               {"modes", ordered_names(results, "modes", "mode")},
               {"trajectories", json::object()}};
  GroundTruths truths;
  for (const json& run : results["runs"]) {
    const std::string preset = run["preset"].get<std::string>(), mode = run["mode"].get<std::string>();
    json& plot = data["trajectories"][preset];
    if (plot.is_null()) plot = {{"modes", json::object()}, {"notes", json::array()}};
    // bench_dynamic writes each run to runs/PRESET/MODE (and names it in "run_dir").
    const fs::path run_dir = run.contains("run_dir") && run["run_dir"].is_string()
                                 ? bench_dir / run["run_dir"].get<std::string>()
                                 : bench_dir / "runs" / preset / mode;
    add_trajectory(plot, mode, run_dir, truths);
  }
  return data;
}

}  // namespace lrd::report
