#include "lrd/sweep/sweep_tables.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "lrd/eval/improvement.h"
#include "lrd/eval/paper_tables.h"
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
                               {"yardstick_ms", "per_frame/yardstick/median_ms"},
                               // Synthetic sequences (ground-truth masks): the dynamic keypoint
                               // flags, and the recall on each class of what moves.
                               {"flag_precision", "dynamic_flags/precision"},
                               {"flag_recall", "dynamic_flags/recall"},
                               {"person_recall", "dynamic_flags/person_recall"},
                               {"moved_object_recall", "dynamic_flags/moved_object_recall"},
                               {"balloon_recall", "dynamic_flags/balloon_recall"},
                               {"moved_object_keypoints", "dynamic_flags/moved_object_keypoints"},
                               {"balloon_keypoints", "dynamic_flags/balloon_keypoints"}};

struct Group {
  std::string sequence, mode, variant, version, config_hash;
  std::vector<json> summaries;
  std::vector<std::string> errors;
  std::string first_cell;  // the first complete repeat's id (the report draws its trajectory)
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
            {"failed", g.errors.size()},    {"errors", g.errors},
            {"first_cell", g.first_cell}};
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

// The medians of an entry's statistics (results.json's PREFIX_STAT UNIT keys) as one ErrorStats.
std::optional<eval::ErrorStats> median_stats(const json& e, const std::string& prefix, const char* unit) {
  const auto rmse = median_of(e, fmt::format("{}_rmse{}", prefix, unit).c_str());
  if (!rmse) return std::nullopt;
  eval::ErrorStats s;
  s.rmse = *rmse;
  s.mean = median_of(e, fmt::format("{}_mean{}", prefix, unit).c_str()).value_or(0.0);
  s.median = median_of(e, fmt::format("{}_median{}", prefix, unit).c_str()).value_or(0.0);
  s.std_dev = median_of(e, fmt::format("{}_std{}", prefix, unit).c_str()).value_or(0.0);
  return s;
}

// Tables 4-7, eta and Table 10 (eval/paper_tables.h), each cell the median over its repeats.
std::string paper_tables(const Layout& l) {
  eval::PaperTables tables(l.rows, l.modes);
  for (const auto& [key, entry] : l.at) {
    const json& e = *entry;
    eval::PaperCell c;
    c.ate = median_stats(e, "ate", "_m");
    c.rpe_trans = median_stats(e, "rpe_trans", "_m_s");
    c.rpe_rot = median_stats(e, "rpe_rot", "_deg_s");
    c.time_mean_ms = median_of(e, "time_per_frame_mean_ms");
    c.time_median_ms = median_of(e, "time_per_frame_ms");
    c.y_ms = median_of(e, "yardstick_ms");
    tables.set(key.first, key.second, c);
  }
  return tables.error_tables() + tables.improvement_table() + tables.time_table();
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

// The flags of the modes that flag anything, where the runs were scored against ground-truth masks;
// a class's recall only where the sequences show it (moved objects, balloons).
std::string flags_table(const Layout& l) {
  const auto has = [](const json& e, const char* key) { return e.contains(key) && !e[key].is_null(); };
  const auto shows = [&](const char* count) {
    return std::any_of(l.at.begin(), l.at.end(), [&](const auto& kv) {
      const json& e = *kv.second;
      return has(e, count) && e[count]["median"].template get<double>() > 0.0;
    });
  };
  const bool boxes = shows("moved_object_keypoints"), balloons = shows("balloon_keypoints");
  const auto cell = [&](const json& e, const char* key) {
    return has(e, key) ? fmt::format("{:.3f}", e[key]["median"].get<double>()) : std::string("—");
  };
  std::string rows;
  for (const std::string& row : l.rows)
    for (const std::string& m : l.modes) {
      const auto it = l.at.find({row, m});
      if (it == l.at.end() || m == "static" || !has(*it->second, "flag_precision")) continue;
      const json& e = *it->second;
      rows += fmt::format("| {} | {} | {} | {} | {}{}{} |\n", row, m, cell(e, "flag_precision"),
                          cell(e, "flag_recall"), cell(e, "person_recall"),
                          boxes ? " | " + cell(e, "moved_object_recall") : "",
                          balloons ? " | " + cell(e, "balloon_recall") : "");
    }
  if (rows.empty()) return "";
  return fmt::format(
      "### Dynamic keypoint flags vs ground-truth masks (median over repeats)\n\n"
      "| sequence | mode | precision | recall | recall: people{}{} |\n|---|---|---|---|---{}{}|\n{}\n",
      boxes ? " | moved objects" : "", balloons ? " | balloon" : "", boxes ? "|---" : "",
      balloons ? "|---" : "", rows);
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
      g = groups.insert(groups.end(), Group{c.sequence, c.mode, c.variant, version, hash, {}, {}, {}});
    if (done) {
      if (g->summaries.empty()) g->first_cell = c.id;
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
  t.markdown += paper_tables(l);
  t.markdown += spread_table(l);
  t.markdown += flags_table(l);
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
