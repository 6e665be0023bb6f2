// Dense stage benchmark (issue 7): each walking preset in `full` mode, once without and once with
// the dense map (background repair + point cloud in its own thread), alternately and `--repeat`
// times, so the cost of the dense thread to tracking shows as the ratio of the medians (bar: within
// 5 %). The dense runs also report the repair (fill ratio, median depth error vs static/depth) and
// the map (ghosts, completeness vs scene.ply). Time per frame excludes PNG decoding; Y = median
// `cv::ORB` detectAndCompute on the same frames.
//
//   bench_dense [--presets a,b] [--segmenter NAME] [--frames N] [--repeat N] [--realtime] [--cache DIR]
//               [--out FILE.md]
// --realtime feeds the frames at their timestamps' pace, as a live camera does; by default they
// come as fast as they are tracked, so the cores have no idle time for the dense thread.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
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
  std::vector<std::string> presets{"walking_xyz", "walking_static", "walking_halfsphere", "walking_rpy"};
  std::string segmenter, cache = "out/bench/sequences", out_file = "out/bench/dense/dense.md";
  int frames = -1, repeat = 2;
  bool realtime = false;
  app.add_option("--presets", presets, "Synthetic presets")->delimiter(',');
  app.add_option("--segmenter", segmenter, "Segmenter preset (default: fnet if shipped, else gt-masks)");
  app.add_option("--frames", frames, "Frames per sequence (default: the preset's length)");
  app.add_option("--repeat", repeat, "Runs of each configuration (alternating)");
  app.add_option("--cache", cache, "Where generated sequences are kept");
  app.add_option("--out", out_file, "Markdown table");
  app.add_flag("--realtime", realtime, "Feed frames at the camera's pace (30 Hz), as a live camera would");
  CLI11_PARSE(app, argc, argv);
  if (segmenter.empty()) segmenter = fs::exists("models/fnet-lite.onnx") ? "fnet" : "gt-masks";

  std::string md = fmt::format(
      "| sequence | Y ms | without: median ms (× Y) | with dense: median ms (× Y) | ratio | keyframes "
      "repaired | "
      "filled | depth error mm | map points | ghosts > 5 cm | completeness |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::printf("segmenter: %s, full mode, %d runs each%s\n", segmenter.c_str(), repeat,
              realtime ? ", frames fed at the camera's pace" : ", frames fed as fast as they are tracked");
  try {
    for (const std::string& preset : presets) {
      const fs::path dir = lrd::bench::ensure_sequence(cache, preset, frames);
      const double y = lrd::bench::sequence_yardstick_ms(dir);
      std::vector<double> without, with;
      lrd::runner::RunReport dense_report;
      for (int k = 0; k < repeat; ++k)
        for (const bool dense : {false, true}) {
          lrd::runner::RunOptions o;
          o.sequence = dir;
          o.out = fs::path(out_file).parent_path() / "runs" / preset / (dense ? "dense" : "plain");
          o.progress = false;
          o.mode = "full";
          o.segmenter = segmenter;
          o.dense = dense;
          o.realtime = realtime;
          const lrd::runner::RunReport r = lrd::runner::run_sequence(o);
          (dense ? with : without).push_back(r.total.median_ms);
          if (dense) dense_report = r;
        }
      const double a = lrd::bench::median_of(without), b = lrd::bench::median_of(with);
      const auto& d = *dense_report.dense;
      const std::string map = d.map ? fmt::format("{} | {:.2f} % | {:.1f} %", d.map->map_points,
                                                  100 * d.map->ghost_ratio(), 100 * d.map->completeness())
                                    : "– | – | –";
      const std::string line = fmt::format(
          "| {} | {:.2f} | {:.1f} ({:.2f}) | {:.1f} ({:.2f}) | {:.3f} | {} | {:.1f} % | {} | {} |\n", preset,
          y, a, a / y, b, b / y, b / a, d.repair.keyframes, 100 * d.repair.fill_ratio(),
          d.repair_median_depth_error ? fmt::format("{:.1f}", 1e3 * *d.repair_median_depth_error) : "–", map);
      std::fputs(line.c_str(), stdout);
      std::fflush(stdout);
      md += line;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_dense: %s\n", e.what());
    return 1;
  }
  fs::create_directories(fs::path(out_file).parent_path());
  std::ofstream(out_file) << "# Dense map: cost to tracking and quality (full mode, segmenter " << segmenter
                          << (realtime ? ", frames at the camera's pace" : ", frames as fast as tracked")
                          << ")\n\n"
                          << md;
  std::printf("wrote %s\n", out_file.c_str());
  return 0;
}
