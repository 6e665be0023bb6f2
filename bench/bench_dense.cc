// Dense stage benchmark (docs/dense-map.md): each walking preset in `full` mode without the dense
// map, with it (background repair + point cloud in its own thread) and with it and the occupancy
// map (docs/occupancy.md), alternately and `--repeat` times, so the cost of each to tracking shows
// as the ratio of the medians (bar: within 5 %). The dense runs also report the repair (fill ratio,
// median depth error vs static/depth) and the map (ghosts, completeness vs scene.ply); the
// occupancy runs its build time and precision, recall, people ghosts and the people's path on the
// 2-D grid, with one `static`-mode run as the negative control. Time per frame excludes PNG
// decoding; Y = median `cv::ORB` detectAndCompute on the same frames.
//
//   bench_dense [--presets a,b] [--segmenter NAME] [--frames N] [--repeat N] [--realtime] [--cache DIR]
//               [--static-control 0|1] [--out FILE.md]
// --realtime feeds the frames at their timestamps' pace, as a live camera does; by default they
// come as fast as they are tracked, so the cores have no idle time for the dense thread.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench/sequence_cache.h"
#include "lrd/runner/sequence_runner.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  CLI::App app{"bench_dense: cost and quality of the dense map"};
  std::vector<std::string> presets{"walking_xyz", "walking_static", "walking_halfsphere", "walking_rpy",
                                   "walking_loop"};
  std::string segmenter, cache = "out/bench/sequences", out_file = "out/bench/dense/dense.md";
  int frames = -1, repeat = 2;
  bool realtime = false, control = true;
  app.add_option("--presets", presets, "Synthetic presets")->delimiter(',');
  app.add_option("--segmenter", segmenter, "Segmenter preset (default: fnet if shipped, else gt-masks)");
  app.add_option("--frames", frames, "Frames per sequence (default: the preset's length)");
  app.add_option("--repeat", repeat, "Runs of each configuration (alternating)");
  app.add_option("--cache", cache, "Where generated sequences are kept");
  app.add_option("--out", out_file, "Markdown table");
  app.add_flag("--realtime", realtime, "Feed frames at the camera's pace (30 Hz), as a live camera would");
  app.add_option(
      "--static-control", control,
      "Also run static mode with the occupancy map, the negative control (people stay in the grid)");
  std::string realism = "clean";
  app.add_option("--realism", realism,
                 "Realism profile of the rendered sequences (docs/synthetic-benchmark.md)")
      ->check(CLI::IsMember({"clean", "tum"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (segmenter.empty()) segmenter = fs::exists("models/fnet-lite.onnx") ? "fnet" : "gt-masks";

  std::string md = fmt::format(
      "| sequence | Y ms | without: median ms (× Y) | with dense: median ms (× Y) | ratio | keyframes "
      "repaired | "
      "filled | depth error mm | map points | ghosts > 5 cm | completeness |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  // The occupancy map on top of the dense map, and static mode as the negative control.
  std::string occ_md = fmt::format(
      "| sequence | mode | dense: median ms | + occupancy: median ms | ratio | build s (× Y per keyframe) | "
      "precision | recall | people ghosts | grid precision | grid recall | path cells blocked |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::printf("segmenter: %s, full mode, %d runs each%s\n", segmenter.c_str(), repeat,
              realtime ? ", frames fed at the camera's pace" : ", frames fed as fast as they are tracked");
  const auto occupancy_row = [](const std::string& preset, const std::string& mode, const std::string& times,
                                const lrd::runner::RunReport& r, double y) {
    const auto& o = *r.occupancy;
    const std::string build =
        fmt::format("{:.2f} ({:.1f})", o.build_seconds,
                    1e3 * o.build_seconds / std::max(1.0, static_cast<double>(r.map.keyframes)) / y);
    if (!o.accuracy)
      return fmt::format("| {} | {} | {} | {} | – | – | – | – | – | – |\n", preset, mode, times, build);
    const auto& a = *o.accuracy;
    return fmt::format(
        "| {} | {} | {} | {} | {:.1f} % | {:.1f} % | {} ({:.2f} %) | {:.1f} % | {:.1f} % | {} of {} |\n",
        preset, mode, times, build, 100 * a.precision(), 100 * a.recall(), a.people_ghosts,
        100 * a.people_ghost_share(), 100 * a.grid_precision(), 100 * a.grid_recall(), a.path_blocked_cells,
        a.path_cells);
  };
  try {
    for (const std::string& preset : presets) {
      const fs::path dir = lrd::bench::ensure_sequence(cache, preset, frames, 1, realism);
      const double y_apart = lrd::bench::sequence_yardstick_ms(dir);
      std::vector<double> without, with, with_occupancy, run_y;
      lrd::runner::RunReport dense_report, occupancy_report;
      const auto run = [&](const std::string& mode, bool dense, bool occupancy, const std::string& name) {
        lrd::runner::RunOptions o;
        o.sequence = dir;
        o.out = fs::path(out_file).parent_path() / "runs" / preset / name;
        o.progress = false;
        o.mode = mode;
        o.segmenter = segmenter;
        o.dense = dense;
        o.occupancy = occupancy;
        o.realtime = realtime;
        o.yardstick = true;
        lrd::runner::RunReport r = lrd::runner::run_sequence(o);
        run_y.push_back(lrd::bench::run_yardstick_ms(r, y_apart));
        return r;
      };
      for (int k = 0; k < repeat; ++k) {
        without.push_back(run("full", false, false, "plain").total.median_ms);
        dense_report = run("full", true, false, "dense");
        with.push_back(dense_report.total.median_ms);
        occupancy_report = run("full", true, true, "occupancy");
        with_occupancy.push_back(occupancy_report.total.median_ms);
      }
      const double a = lrd::bench::median_of(without), b = lrd::bench::median_of(with),
                   c = lrd::bench::median_of(with_occupancy);
      const double y = lrd::bench::median_of(run_y);  // Y of the runs above (interleaved)
      const auto& d = *dense_report.dense;
      const std::string map = d.map ? fmt::format("{} | {:.2f} % | {:.1f} %", d.map->map_points,
                                                  100 * d.map->ghost_ratio(), 100 * d.map->completeness())
                                    : "– | – | –";
      const std::string line = fmt::format(
          "| {} | {:.2f} | {:.1f} ({:.2f}) | {:.1f} ({:.2f}) | {:.3f} | {} | {:.1f} % | {} | {} |\n", preset,
          y, a, a / y, b, b / y, b / a, d.repair.keyframes, 100 * d.repair.fill_ratio(),
          d.repair_median_depth_error ? fmt::format("{:.1f}", 1e3 * *d.repair_median_depth_error) : "–", map);
      std::fputs(line.c_str(), stdout);
      md += line;
      const std::string occ_line = occupancy_row(
          preset, "full", fmt::format("{:.1f} | {:.1f} | {:.3f}", b, c, c / b), occupancy_report, y);
      std::fputs(occ_line.c_str(), stdout);
      occ_md += occ_line;
      if (control) {
        const lrd::runner::RunReport s = run("static", true, true, "static");
        const std::string s_line =
            occupancy_row(preset, "static", fmt::format("– | {:.1f} | –", s.total.median_ms), s, y);
        std::fputs(s_line.c_str(), stdout);
        occ_md += s_line;
      }
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_dense: %s\n", e.what());
    return 1;
  }
  fs::create_directories(fs::path(out_file).parent_path());
  std::ofstream(out_file) << "# Dense map: cost to tracking and quality (full mode, segmenter " << segmenter
                          << (realtime ? ", frames at the camera's pace" : ", frames as fast as tracked")
                          << ", realism `" << realism << "`"
                          << ")\n\n"
                          << md << "\n## Occupancy map\n\n"
                          << occ_md;
  std::printf("wrote %s\n", out_file.c_str());
  return 0;
}
