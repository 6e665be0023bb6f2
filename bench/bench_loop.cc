// Loop-closing benchmark (bench/results/loop.md): runs the loop presets with and without loop
// closing in one run and prints the ATE of both and their ratio (bar: with <= 0.5 x without), the
// loops found, and the cost per frame as multiples of the yardstick Y.
//
//   bench_loop [--presets static_loop,walking_loop] [--cache DIR] [--frames N] [--markdown FILE]
//              [--threaded]
//
// walking_loop runs in `full` mode (fnet segmentation + geometry check); static_loop in `static`.
// Runs are deterministic (lock-step mapping and loop closing) unless --threaded.
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

int main(int argc, char** argv) {
  CLI::App app{"Loop closing benchmark: ATE with and without loop closing on the loop presets"};
  std::vector<std::string> presets{"static_loop", "walking_loop"};
  std::string cache = "out/bench/sequences", markdown;
  int frames = -1;
  bool threaded = false;
  app.add_option("--presets", presets, "Comma-separated presets")->delimiter(',');
  app.add_option("--cache", cache, "Where generated sequences are kept");
  app.add_option("--frames", frames, "Frames per sequence (default: the preset's length)");
  app.add_option("--markdown", markdown, "Also write the table as Markdown to this file");
  app.add_flag("--threaded", threaded,
               "Threaded mapping and loop closing (default: deterministic lock-step)");
  std::string realism = "clean";
  app.add_option("--realism", realism,
                 "Realism profile of the rendered sequences (docs/synthetic-benchmark.md)")
      ->check(CLI::IsMember({"clean", "tum"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  std::printf("realism profile: %s\n", realism.c_str());
  std::ostringstream md;
  md << "Realism profile `" << realism << "`.\n\n";
  md << "| preset | mode | loops | ATE without LC (cm) | ATE with LC (cm) | with / without | lost | total "
        "median "
        "with LC | / Y |\n|---|---|---|---|---|---|---|---|---|\n";
  std::printf("%-14s %-7s %5s %12s %12s %8s %5s %10s %7s\n", "preset", "mode", "loops", "ATE off cm",
              "ATE on cm", "ratio", "lost", "total ms", "tot/Y");
  for (const std::string& preset : presets) {
    const fs::path dir = lrd::bench::ensure_sequence(cache, preset, frames, 1, realism);
    const double y_apart = lrd::bench::sequence_yardstick_ms(dir);
    const std::string mode = preset.rfind("static", 0) == 0 ? "static" : "full";
    lrd::runner::RunReport reports[2];
    for (int lc = 0; lc < 2; ++lc) {
      lrd::runner::RunOptions o;
      o.sequence = dir;
      o.out = fs::path("out/bench/runs") / fmt::format("{}_{}", preset, lc ? "lc" : "nolc");
      o.progress = false;
      o.deterministic = !threaded;
      o.mode = mode;
      o.no_loop_closing = lc == 0;
      o.yardstick = true;
      reports[lc] = lrd::runner::run_sequence(o);
    }
    const auto& off = reports[0];
    const auto& on = reports[1];
    const double y = lrd::bench::run_yardstick_ms(on, y_apart);  // the run whose time is divided
    const double ratio = off.ate_rmse > 0 ? on.ate_rmse / off.ate_rmse : 0.0;
    std::printf("%-14s %-7s %5zu %12.2f %12.2f %8.2f %5zu %10.1f %7.2f\n", preset.c_str(), mode.c_str(),
                on.loops.size(), 100 * off.ate_rmse, 100 * on.ate_rmse, ratio, on.lost, on.total.median_ms,
                on.total.median_ms / y);
    for (const auto& e : on.loops)
      std::printf("    loop: frame %llu (keyframe %llu) -> keyframe %llu, %d inliers, moved %.3f m\n",
                  static_cast<unsigned long long>(e.frame_id), static_cast<unsigned long long>(e.keyframe_id),
                  static_cast<unsigned long long>(e.loop_keyframe_id), e.inliers, e.correction_m);
    std::fflush(stdout);
    md << fmt::format("| {} | {} | {} | {:.2f} | {:.2f} | {:.2f} | {} | {:.1f} ms | {:.2f} Y |\n", preset,
                      mode, on.loops.size(), 100 * off.ate_rmse, 100 * on.ate_rmse, ratio, on.lost,
                      on.total.median_ms, on.total.median_ms / y);
  }
  std::printf("bar: ATE with loop closing <= 0.5 x without\n");
  if (!markdown.empty()) {
    std::ofstream out(markdown);
    out << md.str();
    std::printf("wrote %s\n", markdown.c_str());
  }
  return 0;
}
