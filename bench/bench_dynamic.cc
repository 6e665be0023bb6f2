// Dynamic-scene benchmark (bench/results/dynamic.md): every mode over the walking, sitting and
// walking_pushed presets in one go, written as the paper's tables — Tables 4-7 (ATE, RPE
// translation, RPE rotation: RMSE / mean / median / std per mode), Table 10 (mean and median
// time per frame per mode, also as multiples of the yardstick Y) and the improvement rate
// eta = (static - mode) / static (Eq. 12) — as Markdown and JSON, plus the dynamic keypoint
// flags' precision and recall against the ground-truth masks; and report.html, the same tables
// with every mode's trajectory per preset (`lrdslam report OUT` writes it again).
//
//   bench_dynamic [--presets a,b] [--modes static,semantic,geometric,full] [--segmenter NAME]
//                 [--sync] [--frames N] [--cache DIR] [--out DIR] [--config FILE]
//
// --segmenter: fnet (our shipped model) when models/fnet-lite.onnx exists, else gt-masks (the
// benchmark's ground truth for people: the upper bound a network can reach). --sync adds a
// `full` run with the paper's synchronous schedule next to the default asynchronous one.
// --config: an lrd-slam YAML config for every run (a setting judged against the defaults by two
// interleaved runs); `full-sync` takes it with segmentation.schedule set to sync.
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/sequence_cache.h"
#include "lrd/eval/improvement.h"
#include "lrd/eval/paper_tables.h"
#include "lrd/report/benchmark_data.h"
#include "lrd/report/html_page.h"
#include "lrd/runner/sequence_runner.h"

namespace fs = std::filesystem;

namespace {

struct Cell {
  std::string preset, mode;
  double y_ms = 0.0;
  lrd::runner::RunReport report;
};

nlohmann::json stats_json(const lrd::eval::ErrorStats& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std_dev}};
}

// The config of a `full-sync` run: --config's (if any) with segmentation.schedule: sync.
fs::path sync_config(const std::string& config, const fs::path& run_dir) {
  YAML::Node root(YAML::NodeType::Map);
  try {
    if (!config.empty()) root = YAML::LoadFile(config);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(config + ": " + e.what());
  }
  root["segmentation"]["schedule"] = "sync";
  fs::create_directories(run_dir);
  const fs::path file = run_dir / "sync.yaml";
  std::ofstream(file) << root << "\n";
  return file;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Dynamic-scene benchmark: all modes over walking, sitting and walking_pushed (paper Tables 4-7, 10)"};
  std::vector<std::string> presets{"walking_static",     "walking_xyz",    "walking_rpy",
                                   "walking_halfsphere", "sitting_static", "sitting_xyz",
                                   "sitting_halfsphere", "walking_pushed"};
  std::vector<std::string> modes{"static", "semantic", "geometric", "full"};
  std::string cache = "out/bench/sequences", out_dir = "out/bench/dynamic", segmenter, config;
  int frames = -1;
  bool sync = false;
  app.add_option("--presets", presets, "Comma-separated presets")->delimiter(',');
  app.add_option("--modes", modes, "Comma-separated modes")->delimiter(',');
  app.add_option("--segmenter", segmenter, "Segmentation preset (default: fnet if shipped, else gt-masks)");
  app.add_flag("--sync", sync, "Also run `full` with the synchronous schedule (mode `full-sync`)");
  app.add_option("--frames", frames, "Frames per sequence (default: the preset's length)");
  app.add_option("--cache", cache, "Where generated sequences are kept");
  app.add_option("--out", out_dir, "Where tables.md, results.json and the runs go");
  app.add_option("--config", config, "lrd-slam YAML config for every run")->check(CLI::ExistingFile);
  std::string realism = "clean";
  app.add_option("--realism", realism,
                 "Realism profile of the rendered sequences (docs/synthetic-benchmark.md)")
      ->check(CLI::IsMember({"clean", "tum"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (segmenter.empty()) segmenter = fs::exists("models/fnet-lite.onnx") ? "fnet" : "gt-masks";
  if (sync) modes.push_back("full-sync");

  std::map<std::string, Cell> cells;
  std::printf("segmenter: %s\n%-19s %-10s %6s %5s %9s %9s %9s %8s %8s %8s %7s %7s\n", segmenter.c_str(),
              "preset", "mode", "frames", "lost", "ATE cm", "RPEt cm/s", "RPEr d/s", "med ms", "mean ms",
              "med/Y", "prec", "recall");
  try {
    for (const std::string& preset : presets) {
      const fs::path dir = lrd::bench::ensure_sequence(cache, preset, frames, 1, realism);
      const double y_apart = lrd::bench::sequence_yardstick_ms(dir);
      for (const std::string& mode : modes) {
        lrd::runner::RunOptions o;
        o.sequence = dir;
        o.out = fs::path(out_dir) / "runs" / preset / mode;
        o.progress = false;
        o.preload = true;  // no decoding thread competing with tracking (ORB-SLAM2's way of timing)
        o.yardstick = true;
        const bool full_sync = mode == "full-sync";
        o.mode = full_sync ? "full" : mode;
        o.segmenter = (mode == "static" || mode == "geometric") ? "none" : segmenter;
        if (!config.empty()) o.config = fs::path(config);
        if (full_sync) o.config = sync_config(config, o.out);
        lrd::runner::RunReport report = lrd::runner::run_sequence(o);
        const double y = lrd::bench::run_yardstick_ms(report, y_apart);
        Cell c{preset, mode, y, std::move(report)};
        const auto& r = c.report;
        std::printf("%-19s %-10s %6zu %5zu %9.2f %9.2f %9.3f %8.1f %8.1f %8.2f %7s %7s\n", preset.c_str(),
                    mode.c_str(), r.frames, r.lost, 100 * r.ate_rmse, 100 * r.rpe_trans_rmse, r.rpe_rot_rmse,
                    r.total.median_ms, r.total.mean_ms, r.total.median_ms / y,
                    r.flags && mode != "static" ? fmt::format("{:.3f}", r.flags->precision()).c_str() : "-",
                    r.flags && mode != "static" ? fmt::format("{:.3f}", r.flags->recall()).c_str() : "-");
        std::fflush(stdout);
        cells.emplace(preset + "/" + mode, std::move(c));
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_dynamic: %s\n", e.what());
    return 1;
  }

  std::ostringstream md;
  md << "# Dynamic-scene benchmark\n\nSegmenter: `" << segmenter << "`. Synthetic presets, seed 1, realism `"
     << realism << "`"
     << (frames > 0 ? fmt::format(", first {} frames", frames) : std::string(", default lengths"))
     << ". Time per frame excludes PNG decoding; Y = median `cv::ORB` detectAndCompute on the same "
        "frames.\n\n";
  using RR = lrd::runner::RunReport;
  // Tables 4-7, eta and Table 10 as `lrdslam sweep` writes them (eval/paper_tables.h).
  lrd::eval::PaperTables tables(presets, modes);
  for (const auto& [key, c] : cells) {
    lrd::eval::PaperCell cell;
    if (c.report.has_ground_truth) {
      cell.ate = c.report.ate;
      cell.rpe_trans = c.report.rpe_trans;
      cell.rpe_rot = c.report.rpe_rot;
    }
    cell.time_mean_ms = c.report.total.mean_ms;
    cell.time_median_ms = c.report.total.median_ms;
    cell.y_ms = c.y_ms;
    tables.set(c.preset, c.mode, cell);
  }
  md << tables.error_tables() << tables.improvement_table() << tables.time_table();

  // Column headers of the tables that compare each mode with `static`.
  auto non_static_header = [&] {
    for (const auto& m : modes)
      if (m != "static") md << " " << m << " |";
    md << "\n|---|";
    for (const auto& m : modes)
      if (m != "static") md << "---|";
    md << "\n";
  };
  nlohmann::json js;
  js["segmenter"] = segmenter;
  js["seed"] = 1;
  js["frames"] = frames;
  js["presets"] = presets;
  js["modes"] = modes;
  md << "\n### Dynamic keypoint flags vs ground-truth masks (precision / recall; recall on moved objects "
        "(boxes, chairs) and balloons)\n\n"
        "| sequence |";
  non_static_header();
  for (const auto& p : presets) {
    md << "| " << p << " |";
    for (const auto& m : modes) {
      if (m == "static") continue;
      const auto it = cells.find(p + "/" + m);
      if (it == cells.end() || !it->second.report.flags) {
        md << " – |";
        continue;
      }
      const auto& f = *it->second.report.flags;
      md << fmt::format(" {:.3f} / {:.3f}{}{} |", f.precision(), f.recall(),
                        f.moved_object > 0 ? fmt::format("; boxes {:.3f}", f.moved_object_recall()) : "",
                        f.balloon > 0 ? fmt::format("; balloon {:.3f}", f.balloon_recall()) : "");
    }
    md << "\n";
  }

  for (const auto& [key, c] : cells) {
    const RR& r = c.report;
    nlohmann::json j = {
        {"preset", c.preset},
        {"mode", c.mode},
        {"run_dir", (fs::path("runs") / c.preset / c.mode).string()},
        {"frames", r.frames},
        {"lost", r.lost},
        {"keyframes", r.map.keyframes},
        {"y_ms", c.y_ms},
        {"time_ms", {{"mean", r.total.mean_ms}, {"median", r.total.median_ms}}},
        {"time_y", {{"mean", r.total.mean_ms / c.y_ms}, {"median", r.total.median_ms / c.y_ms}}},
        {"segmentation", r.segmentation},
        {"mean_mask_age", r.mean_mask_age}};
    if (r.has_ground_truth) {
      j["ate_m"] = stats_json(r.ate);
      j["rpe_trans_m_per_s"] = stats_json(r.rpe_trans);
      j["rpe_rot_deg_per_s"] = stats_json(r.rpe_rot);
    }
    if (r.flags)
      j["flags"] = {{"precision", r.flags->precision()},
                    {"recall", r.flags->recall()},
                    {"person_recall", r.flags->person_recall()},
                    {"moved_object_recall", r.flags->moved_object_recall()},
                    {"balloon_recall", r.flags->balloon_recall()}};
    const auto base = cells.find(c.preset + "/static");
    if (base != cells.end() && c.mode != "static" && r.has_ground_truth)
      j["eta_percent"] = {
          {"ate_rmse", lrd::eval::improvement_percent(base->second.report.ate.rmse, r.ate.rmse)},
          {"rpe_trans_rmse",
           lrd::eval::improvement_percent(base->second.report.rpe_trans.rmse, r.rpe_trans.rmse)},
          {"rpe_rot_rmse", lrd::eval::improvement_percent(base->second.report.rpe_rot.rmse, r.rpe_rot.rmse)}};
    js["runs"].push_back(j);
  }
  fs::create_directories(out_dir);
  std::ofstream(fs::path(out_dir) / "tables.md") << md.str();
  std::ofstream(fs::path(out_dir) / "results.json") << js.dump(2) << "\n";
  std::printf("wrote %s/tables.md and %s/results.json\n", out_dir.c_str(), out_dir.c_str());
  try {
    const fs::path page = fs::path(out_dir) / "report.html";
    lrd::report::write_html_report(page, lrd::report::collect_benchmark_data(out_dir));
    std::printf("wrote %s\n", page.string().c_str());
  } catch (const std::exception& e) {  // the tables stand without the page (e.g. uPlot not fetched)
    std::fprintf(stderr, "bench_dynamic: no report.html: %s\n", e.what());
    return 1;
  }
  return 0;
}
