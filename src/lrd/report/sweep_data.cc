#include "lrd/report/sweep_data.h"

#include <algorithm>
#include <string>
#include <vector>

#include "lrd/util/error.h"

namespace lrd::report {

using nlohmann::json;

namespace {

double median_of(const json& entry, const char* key) {
  return entry.contains(key) && entry[key].is_object() ? entry[key]["median"].get<double>() : 0.0;
}

// {rmse, mean, median, std}: each the median over the repeats of results.json's PREFIX_STAT_UNIT.
json error_stats(const json& e, const std::string& prefix, const std::string& unit) {
  if (!e.contains(prefix + "_rmse" + unit) || e[prefix + "_rmse" + unit].is_null()) return nullptr;
  json s;
  for (const char* stat : {"rmse", "mean", "median", "std"})
    s[stat] = median_of(e, (prefix + "_" + stat + unit).c_str());
  return s;
}

void add_name(json& names, const std::string& name) {
  if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
}

}  // namespace

bool is_sweep_results(const json& results) {
  return results.is_object() && results.value("format", "") == "lrdslam-sweep-results/1";
}

json sweep_as_benchmark(const json& results, const std::filesystem::path& file) {
  if (!results.contains("entries") || !results["entries"].is_array())
    throw file_error(file, "a sweep's results without an \"entries\" list");
  json out = {
      {"runs", json::array()}, {"presets", json::array()}, {"modes", json::array()}, {"repeats", true}};
  for (const json& e : results["entries"]) {
    if (!e.contains("sequence") || !e.contains("mode") || !e["sequence"].is_string() ||
        !e["mode"].is_string())
      throw file_error(file, "a sweep entry without its sequence and mode");
    // Variants and provenances are rows of their own, as in tables.md.
    std::string row = e["sequence"].get<std::string>();
    if (e.value("variant", "default") != "default") row += " (" + e["variant"].get<std::string>() + ")";
    json run = {
        {"preset", row},
        {"mode", e["mode"]},
        {"ate_m", error_stats(e, "ate", "_m")},
        {"rpe_trans_m_per_s", error_stats(e, "rpe_trans", "_m_s")},
        {"rpe_rot_deg_per_s", error_stats(e, "rpe_rot", "_deg_s")},
        {"repeats", e.value("repeats", 0)},
        {"failed", e.value("failed", 0)},
        {"version", e.value("version", "")},
        {"ate_rmse_runs",
         e.contains("ate_rmse_m") && e["ate_rmse_m"].is_object() ? e["ate_rmse_m"]["runs"] : json::array()}};
    if (e.contains("eta_percent")) {
      const json& eta = e["eta_percent"];
      run["eta_percent"] = {{"ate_rmse", eta.value("ate_rmse_m", 0.0)},
                            {"rpe_trans_rmse", eta.value("rpe_trans_rmse_m_s", 0.0)},
                            {"rpe_rot_rmse", eta.value("rpe_rot_rmse_deg_s", 0.0)}};
    }
    const double ms = median_of(e, "time_per_frame_ms"), y = median_of(e, "time_per_frame_y");
    run["time_ms"] = {{"mean", median_of(e, "time_per_frame_mean_ms")}, {"median", ms}};
    run["time_y"] = {
        {"mean", y > 0.0 ? median_of(e, "time_per_frame_mean_ms") * y / std::max(ms, 1e-12) : 0.0},
        {"median", y}};
    run["y_ms"] = median_of(e, "yardstick_ms");
    if (e.contains("first_cell") && e["first_cell"].is_string())
      run["run_dir"] = "cells/" + e["first_cell"].get<std::string>();
    out["runs"].push_back(run);
    add_name(out["presets"], row);
    add_name(out["modes"], e["mode"].get<std::string>());
  }
  return out;
}

}  // namespace lrd::report
