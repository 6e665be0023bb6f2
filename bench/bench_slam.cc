// SLAM core benchmark (issue: SLAM core): runs `lrdslam run`'s pipeline over synthetic presets
// and prints accuracy (ATE/RPE against ground truth) and time per frame, per stage, as
// milliseconds and as multiples of the yardstick Y measured on the same sequence's frames.
//
//   bench_slam [--presets a,b,...] [--cache DIR] [--frames N] [--markdown FILE] [--deterministic]
//
// Sequences are generated once into the cache folder (default out/bench/sequences, seed 1,
// default lengths). Default presets: the three static ones (bar: no lost frames, ATE <= 1 cm;
// median time per frame <= 2 Y) and the walking ones, whose static-world ATE is the
// "ORB-SLAM2 row" the dynamic mode has to beat.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bench/yardstick.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/synth/sequence_writer.h"
#include "lrd/synth/synthetic_sequence.h"

namespace fs = std::filesystem;

namespace {

fs::path ensure_sequence(const fs::path& cache, const std::string& preset, int frames) {
  const fs::path dir = cache / (frames > 0 ? fmt::format("{}_{}", preset, frames) : preset);
  if (fs::exists(dir / "associations.txt")) return dir;
  std::fprintf(stderr, "generating %s into %s ...\n", preset.c_str(), dir.string().c_str());
  lrd::synth::SynthOptions o;
  o.preset = preset;
  o.seed = 1;
  o.frames = frames;
  const lrd::synth::SyntheticSequence seq(o);
  (void)lrd::synth::write_sequence(seq, dir);
  return dir;
}

// Y on (up to) 100 evenly spread grey frames of the sequence.
double yardstick(const fs::path& dir) {
  const auto seq = lrd::io::TumSequence::open(dir);
  std::vector<cv::Mat> grey;
  const std::size_t step = std::max<std::size_t>(1, seq.size() / 100);
  for (std::size_t i = 0; i < seq.size(); i += step)
    grey.push_back(cv::imread(seq.entry(i).rgb_path.string(), cv::IMREAD_GRAYSCALE));
  return lrd::bench::yardstick_ms(grey);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"SLAM core benchmark: accuracy and time per frame on synthetic presets"};
  std::vector<std::string> presets{"static_xyz",   "static_halfsphere",  "static_loop", "walking_static",
                                   "walking_xyz",  "walking_rpy",        "walking_halfsphere"};
  std::string cache = "out/bench/sequences", markdown;
  int frames = -1;
  bool deterministic = false;
  app.add_option("--presets", presets, "Comma-separated presets")->delimiter(',');
  app.add_option("--cache", cache, "Where generated sequences are kept");
  app.add_option("--frames", frames, "Frames per sequence (default: the preset's length)");
  app.add_option("--markdown", markdown, "Also write the table as Markdown to this file");
  app.add_flag("--deterministic", deterministic, "Lock-step local mapping");
  CLI11_PARSE(app, argc, argv);

  std::ostringstream md;
  md << "| preset | frames | lost | KFs | ATE RMSE (cm) | RPE (cm/s, deg/s) | extraction | tracking | waiting | "
        "total median | total / Y | Y (ms) |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::printf("%-19s %6s %5s %4s %9s %16s %10s %9s %8s %12s %9s %7s\n", "preset", "frames", "lost", "KFs", "ATE cm",
              "RPE cm/s deg/s", "extract ms", "track ms", "wait ms", "total ms", "total/Y", "Y ms");
  for (const std::string& preset : presets) {
    const fs::path dir = ensure_sequence(cache, preset, frames);
    const double y = yardstick(dir);
    lrd::runner::RunOptions o;
    o.sequence = dir;
    o.out = fs::path("out/bench/runs") / preset;
    o.progress = false;
    o.deterministic = deterministic;
    const lrd::runner::RunReport r = lrd::runner::run_sequence(o);
    const std::string rpe = fmt::format("{:.2f} {:.2f}", 100 * r.rpe_trans_rmse, r.rpe_rot_rmse);
    std::printf("%-19s %6zu %5zu %4zu %9.2f %16s %10.1f %9.1f %8.1f %12.1f %9.2f %7.1f\n", preset.c_str(), r.frames,
                r.lost, r.map.keyframes, 100 * r.ate_rmse, rpe.c_str(), r.extraction.median_ms,
                r.tracking.median_ms, r.waiting.median_ms, r.total.median_ms, r.total.median_ms / y, y);
    std::fflush(stdout);
    md << fmt::format("| {} | {} | {} | {} | {:.2f} | {} | {:.1f} ms | {:.1f} ms | {:.1f} ms | {:.1f} ms | {:.2f} Y | {:.1f} |\n",
                      preset, r.frames, r.lost, r.map.keyframes, 100 * r.ate_rmse, rpe, r.extraction.median_ms,
                      r.tracking.median_ms, r.waiting.median_ms, r.total.median_ms, r.total.median_ms / y, y);
  }
  std::printf("time per frame excludes PNG decoding (own thread); bar: total median <= 2 Y\n");
  if (!markdown.empty()) {
    std::ofstream out(markdown);
    out << md.str();
    std::printf("wrote %s\n", markdown.c_str());
  }
  return 0;
}
