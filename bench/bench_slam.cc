// SLAM core benchmark (bench/results/slam_core.md): runs `lrdslam run`'s pipeline over synthetic presets
// and prints accuracy (ATE/RPE against ground truth) and time per frame, per stage, as
// milliseconds and as multiples of the yardstick Y measured on the same sequence's frames.
//
//   bench_slam [--presets a,b,...] [--cache DIR] [--frames N] [--markdown FILE] [--deterministic]
//              [--mode M] [--loop-closing]
//
// Sequences are generated once into the cache folder (default out/bench/sequences, seed 1,
// default lengths). Default presets: the three static ones (bar: no lost frames, ATE <= 1 cm;
// median time per frame <= 2 Y) and the walking ones, whose static-world ATE is the
// "ORB-SLAM2 row" the dynamic mode has to beat. Loop closing stays off unless asked for: the
// SLAM core's bars are without it (bench_loop measures it). Frames are decoded before tracking
// starts, so no decoding thread competes for the cores (ORB-SLAM2's way of timing).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench/sequence_cache.h"
#include "lrd/runner/sequence_runner.h"

namespace fs = std::filesystem;

using lrd::bench::ensure_sequence;

int main(int argc, char** argv) {
  CLI::App app{"SLAM core benchmark: accuracy and time per frame on synthetic presets"};
  std::vector<std::string> presets{"static_xyz",  "static_halfsphere", "static_loop",       "walking_static",
                                   "walking_xyz", "walking_rpy",       "walking_halfsphere"};
  std::string cache = "out/bench/sequences", markdown;
  int frames = -1;
  bool deterministic = false, loop_closing = false;
  std::string mode = "static";
  app.add_option("--presets", presets, "Comma-separated presets")->delimiter(',');
  app.add_option("--cache", cache, "Where generated sequences are kept");
  app.add_option("--frames", frames, "Frames per sequence (default: the preset's length)");
  app.add_option("--markdown", markdown, "Also write the table as Markdown to this file");
  app.add_flag("--deterministic", deterministic, "Lock-step local mapping");
  app.add_flag("--loop-closing", loop_closing,
               "Run with loop closing (off: the SLAM core's bars are without it)");
  app.add_option("--mode", mode,
                 "Dynamic-scene mode (default static: the SLAM core alone, the ORB-SLAM2 row)");
  std::string realism = "clean";
  app.add_option("--realism", realism,
                 "Realism profile of the rendered sequences (docs/synthetic-benchmark.md)")
      ->check(CLI::IsMember({"clean", "tum"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  std::printf("realism profile: %s\n", realism.c_str());
  std::ostringstream md;
  md << "Realism profile `" << realism << "`.\n\n";
  md << "| preset | frames | lost | KFs | ATE RMSE (cm) | RPE (cm/s, deg/s) | extraction | tracking | "
        "waiting | "
        "total median | total / Y | Y (ms) |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::printf("%-19s %6s %5s %4s %9s %16s %10s %9s %8s %12s %9s %7s\n", "preset", "frames", "lost", "KFs",
              "ATE cm", "RPE cm/s deg/s", "extract ms", "track ms", "wait ms", "total ms", "total/Y", "Y ms");
  for (const std::string& preset : presets) {
    const fs::path dir = ensure_sequence(cache, preset, frames, 1, realism);
    const double y_apart = lrd::bench::sequence_yardstick_ms(dir);
    lrd::runner::RunOptions o;
    o.sequence = dir;
    o.out = fs::path("out/bench/runs") / preset;
    o.progress = false;
    o.deterministic = deterministic;
    o.mode = mode;
    o.no_loop_closing = !loop_closing;
    o.preload = true;
    o.yardstick = true;
    const lrd::runner::RunReport r = lrd::runner::run_sequence(o);
    const double y = lrd::bench::run_yardstick_ms(r, y_apart);
    const std::string rpe = fmt::format("{:.2f} {:.2f}", 100 * r.rpe_trans_rmse, r.rpe_rot_rmse);
    std::printf("%-19s %6zu %5zu %4zu %9.2f %16s %10.1f %9.1f %8.1f %12.1f %9.2f %7.1f\n", preset.c_str(),
                r.frames, r.lost, r.map.keyframes, 100 * r.ate_rmse, rpe.c_str(), r.extraction.median_ms,
                r.tracking.median_ms, r.waiting.median_ms, r.total.median_ms, r.total.median_ms / y, y);
    std::fflush(stdout);
    md << fmt::format(
        "| {} | {} | {} | {} | {:.2f} | {} | {:.1f} ms | {:.1f} ms | {:.1f} ms | {:.1f} ms | {:.2f} Y | "
        "{:.1f} |\n",
        preset, r.frames, r.lost, r.map.keyframes, 100 * r.ate_rmse, rpe, r.extraction.median_ms,
        r.tracking.median_ms, r.waiting.median_ms, r.total.median_ms, r.total.median_ms / y, y);
  }
  std::printf("frames decoded before tracking; loop closing %s; bar: total median <= 2 Y\n",
              loop_closing ? "on" : "off");
  if (!markdown.empty()) {
    std::ofstream out(markdown);
    out << md.str();
    std::printf("wrote %s\n", markdown.c_str());
  }
  return 0;
}
