// Map-file benchmark (docs/map-files.md): session 1 of a preset builds and saves a map; session 2
// (the same room from another standpoint) relocalizes in it and tracks it, localization only and
// extending it. Prints the file size per keyframe, load and save times, the relocalization latency
// (frames from the first frame where session 2 sees mapped structure, and the time of a frame spent
// relocalizing) as multiples of Y, and the ATE of session 2 in the world frame of session 1 (the
// alignment of the map's own run, no fit of its own).
//
//   bench_map_file [--presets static_xyz,walking_xyz] [--cache DIR] [--frames N] [--markdown FILE]
//
// Static presets run in `static` mode, walking ones in `full`; runs are deterministic.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench/sequence_cache.h"
#include "lrd/eval/ate.h"
#include "lrd/io/trajectory.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/util/binary_io.h"

namespace fs = std::filesystem;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct FileTimes {
  double load_ms = 0.0, save_ms = 0.0;
  bool same_bytes = false;
};

// Loads the map into a fresh system and saves it again (bag-of-words vectors included in the load).
FileTimes time_load_and_save(const lrd::runner::RunOptions& o, const fs::path& map, const fs::path& again) {
  const lrd::config::Config cfg = lrd::runner::resolve_config(o);
  lrd::SystemOptions sopts;
  sopts.deterministic = true;
  lrd::System slam(cfg, lrd::runner::configure_system(o, cfg), sopts);
  FileTimes t;
  auto t0 = std::chrono::steady_clock::now();
  slam.load_map(map);
  t.load_ms = 1e3 * seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  slam.save_map(again);
  t.save_ms = 1e3 * seconds_since(t0);
  t.same_bytes = lrd::util::read_file_bytes(map, "map") == lrd::util::read_file_bytes(again, "map");
  return t;
}

// ATE of a run's trajectory under a given alignment.
double ate_cm(const fs::path& sequence, const fs::path& out, const Eigen::Isometry3d& alignment) {
  const auto gt = lrd::io::read_trajectory_tum(sequence / "groundtruth.txt");
  const auto est = lrd::io::read_trajectory_tum(out / "CameraTrajectory.txt");
  return 100.0 * lrd::eval::compute_ate(gt, est, alignment).stats.rmse;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Map files: size, load/save time, relocalization latency and session-2 accuracy"};
  std::vector<std::string> presets{"static_xyz", "walking_xyz"};
  std::string cache = "out/bench/sequences", markdown;
  int frames = -1;
  app.add_option("--presets", presets, "Comma-separated presets")->delimiter(',');
  app.add_option("--cache", cache, "Where generated sequences are kept");
  app.add_option("--frames", frames, "Frames per session (default: the preset's length)");
  app.add_option("--markdown", markdown, "Also write the table as Markdown to this file");
  CLI11_PARSE(app, argc, argv);

  std::ostringstream md;
  md << "| preset | mode | Y ms | keyframes | KB / keyframe | load | save | same bytes | first view | "
        "localized | latency (frames) | relocalizing / Y | loc-only ATE (cm) | extended ATE (cm) | loops "
        "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& preset : presets) {
    const std::string mode = preset.rfind("static", 0) == 0 ? "static" : "full";
    const fs::path s1 = lrd::bench::ensure_sequence(cache, preset, frames, 1);
    const fs::path s2 = lrd::bench::ensure_sequence(cache, preset, frames, 2);
    const double y_apart = lrd::bench::sequence_yardstick_ms(s2);
    const fs::path out = fs::path("out/bench/map_file") / preset;

    // Session 1 saves the map it builds; its alignment to the truth is every session's world frame.
    lrd::runner::RunOptions o1;
    o1.sequence = s1;
    o1.out = out / "session1";
    o1.mode = mode;
    o1.progress = false;
    o1.deterministic = true;
    o1.save_map = out / "session1.lrdmap";
    o1.yardstick = true;  // and the sessions below, copied from o1
    const lrd::runner::RunReport r1 = lrd::runner::run_sequence(o1);
    const Eigen::Isometry3d alignment =
        lrd::eval::compute_ate(lrd::io::read_trajectory_tum(s1 / "groundtruth.txt"),
                               lrd::io::read_trajectory_tum(o1.out / "CameraTrajectory.txt"))
            .alignment;
    const double kb_per_keyframe = static_cast<double>(fs::file_size(*o1.save_map)) / 1024.0 /
                                   static_cast<double>(std::max<std::size_t>(1, r1.map.keyframes));
    const FileTimes times = time_load_and_save(o1, *o1.save_map, out / "again.lrdmap");

    // Session 2 loads the map: localization only, then extending it.
    lrd::runner::RunOptions o2 = o1;
    o2.sequence = s2;
    o2.out = out / "session2_localization";
    o2.save_map.reset();
    o2.load_map = o1.save_map;
    o2.localization_only = true;
    const lrd::runner::RunReport r2 = lrd::runner::run_sequence(o2);
    lrd::runner::RunOptions o3 = o2;
    o3.out = out / "session2_extended";
    o3.localization_only = false;
    o3.save_map = out / "merged.lrdmap";
    const lrd::runner::RunReport r3 = lrd::runner::run_sequence(o3);
    const double loc_ate = ate_cm(s2, o2.out, alignment), ext_ate = ate_cm(s2, o3.out, alignment);
    const double y = lrd::bench::median_of({lrd::bench::run_yardstick_ms(r1, y_apart),
                                            lrd::bench::run_yardstick_ms(r2, y_apart),
                                            lrd::bench::run_yardstick_ms(r3, y_apart)});

    const auto index = [](const std::optional<std::size_t>& v) { return v ? std::to_string(*v) : "-"; };
    std::printf(
        "%s (%s): Y %.1f ms; session 1 made %zu keyframes, %.0f KB/keyframe, ATE %.2f cm; "
        "load %.1f ms (%.2f Y), save %.1f ms (%.2f Y), same bytes: %s\n",
        preset.c_str(), mode.c_str(), y, r1.map.keyframes, kb_per_keyframe, 100 * r1.ate_rmse, times.load_ms,
        times.load_ms / y, times.save_ms, times.save_ms / y, times.same_bytes ? "yes" : "NO");
    std::printf(
        "  session 2 in localization-only mode: first view of the map at frame %s, "
        "localized at %s (%s frames), %.1f ms a frame while relocalizing (%.2f Y); %zu/%zu tracked; "
        "ATE in the map's frame %.2f cm; keyframes %zu -> %zu\n",
        index(r2.localization.first_view_frame).c_str(), index(r2.localization.first_localized_frame).c_str(),
        index(r2.localization.frames()).c_str(), r2.not_localized_median_ms, r2.not_localized_median_ms / y,
        r2.tracked, r2.frames, loc_ate, r2.map.loaded_keyframes, r2.map.keyframes);
    std::printf(
        "  session 2 in map-extending mode: %zu loops, keyframes %zu -> %zu, "
        "ATE in the map's frame %.2f cm\n",
        r3.loops.size(), r3.map.loaded_keyframes, r3.map.keyframes, ext_ate);
    std::fflush(stdout);
    md << fmt::format(
        "| {} | {} | {:.1f} | {} | {:.0f} | {:.1f} ms ({:.2f} Y) | {:.1f} ms ({:.2f} Y) | {} | {} | {} | {} "
        "| "
        "{:.1f} ms ({:.2f} Y) | {:.2f} | {:.2f} | {} |\n",
        preset, mode, y, r1.map.keyframes, kb_per_keyframe, times.load_ms, times.load_ms / y, times.save_ms,
        times.save_ms / y, times.same_bytes ? "yes" : "no", index(r2.localization.first_view_frame),
        index(r2.localization.first_localized_frame), index(r2.localization.frames()),
        r2.not_localized_median_ms, r2.not_localized_median_ms / y, loc_ate, ext_ate, r3.loops.size());
  }
  std::printf(
      "bars: session 2 is localized within 30 frames of its first view; loc-only ATE < 1 cm static, "
      "< 2 cm walking (full)\n");
  if (!markdown.empty()) {
    std::ofstream(markdown) << md.str();
    std::printf("wrote %s\n", markdown.c_str());
  }
  return 0;
}
