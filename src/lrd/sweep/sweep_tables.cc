#include "lrd/sweep/sweep_tables.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "lrd/eval/improvement.h"
#include "lrd/eval/statistics.h"
#include "lrd/sweep/cell_runner.h"
#include "lrd/util/binary_io.h"

namespace lrd::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A figure of summary.json by its path ("ate/rmse"); nullopt when the run has none.
std::optional<double> figure(const json& summary, const std::string& path) {
  const json* node = &summary;
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t slash = std::min(path.find('/', start), path.size());
    const std::string key = path.substr(start, slash - start);
    if (!node->is_object() || !node->contains(key)) return std::nullopt;
    node = &(*node)[key];
    start = slash + 1;
  }
  return node->is_number() ? std::optional<double>(node->get<double>()) : std::nullopt;
}

// Every figure the tables show: the results.json key, and where a run's summary.json holds it.
struct Metric {
  const char* key;
  const char* path;
};
constexpr Metric kMetrics[] = {{"ate_rmse_m", "ate/rmse"},
                               {"ate_mean_m", "ate/mean"},
                               {"ate_median_m", "ate/median"},
                               {"ate_std_m", "ate/std"},
                               {"rpe_trans_rmse_m_s", "rpe/trans/rmse"},
                               {"rpe_trans_mean_m_s", "rpe/trans/mean"},
                               {"rpe_trans_median_m_s", "rpe/trans/median"},
                               {"rpe_trans_std_m_s", "rpe/trans/std"},
                               {"rpe_rot_rmse_deg_s", "rpe/rot/rmse"},
                               {"rpe_rot_mean_deg_s", "rpe/rot/mean"},
                               {"rpe_rot_median_deg_s", "rpe/rot/median"},
                               {"rpe_rot_std_deg_s", "rpe/rot/std"},
                               {"time_per_frame_ms", "per_frame/total/median_ms"},
                               {"time_per_frame_mean_ms", "per_frame/total/mean_ms"},
                               {"yardstick_ms", "per_frame/yardstick/median_ms"}};

struct Group {
  std::string sequence, mode, variant, version, config_hash;
  std::vector<json> summaries;
  std::vector<std::string> errors;
};

json spread_json(std::vector<double> runs) {
  if (runs.empty()) return nullptr;
  const double med = eval::median(runs);
  const auto [lo, hi] = std::minmax_element(runs.begin(), runs.end());
  return {{"runs", runs}, {"median", med}, {"min", *lo}, {"max", *hi}, {"spread", *hi - *lo}};
}

json group_json(const Group& g) {
  json e = {{"sequence", g.sequence},       {"mode", g.mode},
            {"variant", g.variant},         {"version", g.version},
            {"config_hash", g.config_hash}, {"repeats", g.summaries.size()},
            {"failed", g.errors.size()},    {"errors", g.errors}};
  for (const Metric& m : kMetrics) {
    std::vector<double> runs;
    for (const json& s : g.summaries)
      if (auto v = figure(s, m.path)) runs.push_back(*v);
    e[m.key] = spread_json(runs);
  }
  std::vector<double> in_y, lost;
  for (const json& s : g.summaries) {
    const auto t = figure(s, "per_frame/total/median_ms");
    const auto y = figure(s, "per_frame/yardstick/median_ms");
    if (t && y && *y > 0.0) in_y.push_back(*t / *y);
    lost.push_back(figure(s, "lost").value_or(0.0));
  }
  e["time_per_frame_y"] = spread_json(in_y);
  e["lost_frames"] = spread_json(lost);
  return e;
}

std::optional<double> median_of(const json& entry, const char* key) {
  if (!entry.contains(key) || entry[key].is_null()) return std::nullopt;
  return entry[key]["median"].get<double>();
}

// eta over the `static` entry of the same sequence, variant and provenance.
void add_improvement(json& entries) {
  for (json& e : entries) {
    json eta = json::object();
    for (const json& base : entries) {
      if (base["mode"] != "static" || base["sequence"] != e["sequence"] || base["variant"] != e["variant"] ||
          base["version"] != e["version"] || base["config_hash"] != e["config_hash"])
        continue;
      for (const char* key : {"ate_rmse_m", "rpe_trans_rmse_m_s", "rpe_rot_rmse_deg_s"}) {
        const auto b = median_of(base, key), o = median_of(e, key);
        if (b && o) eta[key] = eval::improvement_percent(*b, *o);
      }
    }
    e["eta_percent"] = eta;
  }
}

std::string cell_text(const json& e, const char* key, int digits) {
  const auto v = median_of(e, key);
  return v ? fmt::format("{:.{}f}", *v, digits) : std::string("—");
}

// The row label: the sequence, and the variant and provenance where they tell rows apart.
std::string row_label(const json& e, bool variants, bool provenances) {
  std::string label = e["sequence"].get<std::string>();
  if (variants) label += fmt::format(" ({})", e["variant"].get<std::string>());
  if (provenances)
    label += fmt::format(" [{} {}]", e["version"].get<std::string>(),
                         e["config_hash"].get<std::string>().substr(0, 8));
  return label;
}

struct Layout {
  std::vector<std::string> rows, modes;
  std::map<std::pair<std::string, std::string>, const json*> at;  // (row, mode) -> entry
};

Layout layout(const json& entries, const std::vector<std::string>& modes) {
  std::set<std::string> variants, provenances;
  for (const json& e : entries) {
    variants.insert(e["variant"].get<std::string>());
    provenances.insert(e["version"].get<std::string>() + e["config_hash"].get<std::string>());
  }
  Layout l;
  l.modes = modes;
  for (const json& e : entries) {
    const std::string row = row_label(e, variants.size() > 1, provenances.size() > 1);
    if (std::find(l.rows.begin(), l.rows.end(), row) == l.rows.end()) l.rows.push_back(row);
    l.at[{row, e["mode"].get<std::string>()}] = &e;
  }
  return l;
}

// One of Tables 4-7: per mode the median over repeats of RMSE, mean, median and std of the
// results.json keys PREFIX_STAT UNIT (ate_rmse_m, rpe_trans_mean_m_s, ...).
std::string error_table(const Layout& l, const std::string& title, const std::string& prefix,
                        const char* unit, int digits) {
  std::string md = fmt::format("### {}\n\n| sequence |", title);
  for (const std::string& m : l.modes) md += fmt::format(" {0} RMSE | {0} mean | {0} median | {0} std |", m);
  md += "\n|---|";
  for (std::size_t i = 0; i < l.modes.size(); ++i) md += "---|---|---|---|";
  md += "\n";
  for (const std::string& row : l.rows) {
    md += fmt::format("| {} |", row);
    for (const std::string& m : l.modes) {
      const auto it = l.at.find({row, m});
      for (const char* stat : {"rmse", "mean", "median", "std"}) {
        // fmt, not string concatenation: gcc 12 warns of a false overflow in operator+ here.
        const std::string key = fmt::format("{}_{}{}", prefix, stat, unit);
        md += fmt::format(" {} |",
                          it == l.at.end() ? std::string("—") : cell_text(*it->second, key.c_str(), digits));
      }
    }
    md += "\n";
  }
  return md + "\n";
}

std::string spread_table(const Layout& l) {
  std::string md =
      "### ATE RMSE over repeats (m): median [min, max], spread; runs done / failed; lost frames (median)\n\n"
      "| sequence | mode | median | min | max | spread | done | failed | lost | eta ATE (%) |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& row : l.rows)
    for (const std::string& m : l.modes) {
      const auto it = l.at.find({row, m});
      if (it == l.at.end()) continue;
      const json& e = *it->second;
      const json& a = e["ate_rmse_m"];
      const std::string eta = e["eta_percent"].contains("ate_rmse_m") && m != "static"
                                  ? fmt::format("{:+.1f}", e["eta_percent"]["ate_rmse_m"].get<double>())
                                  : "";
      md += a.is_null()
                ? fmt::format("| {} | {} | — | — | — | — | {} | {} | — | |\n", row, m,
                              e["repeats"].get<int>(), e["failed"].get<int>())
                : fmt::format("| {} | {} | {:.4f} | {:.4f} | {:.4f} | {:.4f} | {} | {} | {} | {} |\n", row, m,
                              a["median"].get<double>(), a["min"].get<double>(), a["max"].get<double>(),
                              a["spread"].get<double>(), e["repeats"].get<int>(), e["failed"].get<int>(),
                              e["lost_frames"]["median"].get<double>(), eta);
    }
  return md + "\n";
}

std::string time_table(const Layout& l) {
  std::string md =
      "### Table 10: time per frame (median over repeats of each run's median; ms, and Y of the same "
      "run)\n\n| sequence |";
  for (const std::string& m : l.modes) md += fmt::format(" {0} ms | {0} Y |", m);
  md += "\n|---|";
  for (std::size_t i = 0; i < l.modes.size(); ++i) md += "---|---|";
  md += "\n";
  for (const std::string& row : l.rows) {
    md += fmt::format("| {} |", row);
    for (const std::string& m : l.modes) {
      const auto it = l.at.find({row, m});
      md += it == l.at.end() ? std::string(" — | — |")
                             : fmt::format(" {} | {} |", cell_text(*it->second, "time_per_frame_ms", 2),
                                           cell_text(*it->second, "time_per_frame_y", 2));
    }
    md += "\n";
  }
  return md + "\n";
}

}  // namespace

SweepTables collect_tables(const fs::path& dir, const std::vector<SweepCell>& cells) {
  SweepTables t;
  std::vector<Group> groups;
  std::vector<std::string> modes;
  json failures = json::array();
  for (const SweepCell& c : cells) {
    if (std::find(modes.begin(), modes.end(), c.mode) == modes.end()) modes.push_back(c.mode);
    const std::optional<json> record = cell_record(dir, c);
    if (!record) {
      ++t.missing;
      continue;
    }
    const bool done = record->contains("summary");
    (done ? t.done : t.failed) += 1;
    const std::string version = record->value("version", "?"), hash = record->value("config_hash", "?");
    auto g = std::find_if(groups.begin(), groups.end(), [&](const Group& x) {
      return x.sequence == c.sequence && x.mode == c.mode && x.variant == c.variant && x.version == version &&
             x.config_hash == hash;
    });
    if (g == groups.end())
      g = groups.insert(groups.end(), Group{c.sequence, c.mode, c.variant, version, hash, {}, {}});
    if (done) {
      g->summaries.push_back((*record)["summary"]);
    } else {
      g->errors.push_back(record->value("error", "failed"));
      failures.push_back({{"cell", c.id}, {"error", record->value("error", "failed")}});
    }
  }
  json entries = json::array();
  for (const Group& g : groups) entries.push_back(group_json(g));
  add_improvement(entries);
  t.results = {{"format", "lrdslam-sweep-results/1"},
               {"cells", cells.size()},
               {"done", t.done},
               {"failed", t.failed},
               {"missing", t.missing},
               {"entries", entries},
               {"failures", failures}};
  const Layout l = layout(t.results["entries"], modes);
  t.markdown = fmt::format(
      "# Sweep {}\n\n{} cells: {} done, {} failed, {} missing. Each figure is the median over a "
      "cell's repeats.\n\n",
      fs::absolute(dir).lexically_normal().string(), cells.size(), t.done, t.failed, t.missing);
  t.markdown += error_table(l, "Tables 4-5: ATE (m)", "ate", "_m", 4);
  t.markdown += error_table(l, "Table 6: RPE translation (m/s)", "rpe_trans", "_m_s", 4);
  t.markdown += error_table(l, "Table 7: RPE rotation (deg/s)", "rpe_rot", "_deg_s", 3);
  t.markdown += time_table(l);
  t.markdown += spread_table(l);
  for (const json& f : failures)
    t.markdown +=
        fmt::format("- failed: {}: {}\n", f["cell"].get<std::string>(), f["error"].get<std::string>());
  return t;
}

void write_tables(const fs::path& dir, const SweepTables& tables) {
  util::write_file_bytes(dir / "results.json", tables.results.dump(1) + "\n");
  util::write_file_bytes(dir / "tables.md", tables.markdown);
}

}  // namespace lrd::sweep
