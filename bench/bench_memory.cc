// Map memory benchmark (bench/results/memory.md): a long run over one synthetic preset, played
// forwards and backwards so that the camera keeps revisiting the same room (as a robot patrolling
// it would), printing every N frames the resident memory of the process, the map's size, the
// bytes one keyframe and one map point hold, what deferred reclamation freed so far, and the time
// per frame against the yardstick Y.
//
//   bench_memory [--preset walking_loop] [--frames 6000] [--every 1000] [--mode static]
//                [--cache DIR] [--deterministic] [--markdown FILE]
//
// Frames are decoded as they are tracked (nothing preloaded), so the resident memory is the
// system's. The dense map is off: its clouds are the dense stage's, not the map's. The ATE over
// the whole run (ground truth played the same way) says whether the map stayed sound.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bench/resident_memory.h"
#include "bench/sequence_cache.h"
#include "lrd/eval/ate.h"
#include "lrd/io/trajectory.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/system.h"

namespace fs = std::filesystem;

namespace {

using lrd::bench::resident_mib;

// Frame k of a ping-pong playback of n frames: 0, 1, ..., n-1, n-2, ..., 1, 0, 1, ...
std::size_t ping_pong(std::size_t k, std::size_t n) {
  if (n < 2) return 0;
  const std::size_t period = 2 * n - 2;
  const std::size_t r = k % period;
  return r < n ? r : period - r;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Map memory benchmark: resident memory, bytes per keyframe and map point over a long run"};
  std::string preset = "walking_loop", cache = "out/bench/sequences", markdown, mode = "static";
  int frames = 6000, every = 1000;
  bool deterministic = false;
  app.add_option("--preset", preset, "Synthetic preset, played forwards and backwards");
  app.add_option("--frames", frames, "Frames in the run")->check(CLI::PositiveNumber);
  app.add_option("--every", every, "Print a row every N frames")->check(CLI::PositiveNumber);
  app.add_option("--mode", mode, "Dynamic-scene mode");
  app.add_option("--cache", cache, "Where generated sequences are kept");
  app.add_flag("--deterministic", deterministic, "Lock-step local mapping");
  app.add_option("--markdown", markdown, "Also write the table as Markdown to this file");
  CLI11_PARSE(app, argc, argv);

  const fs::path dir = lrd::bench::ensure_sequence(cache, preset, -1);
  const double y_apart = lrd::bench::sequence_yardstick_ms(dir);
  lrd::runner::RunOptions o;
  o.sequence = dir;
  o.mode = mode;
  o.deterministic = deterministic;
  const lrd::config::Config cfg = lrd::runner::resolve_config(o);
  const lrd::SystemParams params = lrd::runner::configure_system(o, cfg);
  lrd::SystemOptions options;
  options.deterministic = deterministic;
  options.yardstick = true;  // Y timed in the tracking thread beside each frame's extraction
  const auto seq = lrd::io::TumSequence::open(dir);
  std::printf(
      "bench_memory: %s (%zu frames, played forwards and backwards) for %d frames, mode %s, %s; "
      "Y measured apart before the run (the old basis) = %.2f ms; the ratios below divide by each row's "
      "interleaved Y (OpenCV ORB in the tracking thread, every frame, not in the frame's time)\n",
      preset.c_str(), seq.size(), frames, mode.c_str(), deterministic ? "deterministic" : "threaded",
      y_apart);
  const double rss_before = resident_mib();
  // Ground truth of the playback: the pose of the frame shown at each playback time.
  const lrd::io::Trajectory truth = lrd::io::read_trajectory_tum(seq.groundtruth_path().value());
  auto truth_at = [&truth](double t) {
    const auto it = std::lower_bound(truth.begin(), truth.end(), t - 1e-4,
                                     [](const lrd::io::StampedPose& p, double x) { return p.timestamp < x; });
    return it == truth.end() ? truth.back().pose : it->pose;
  };
  lrd::io::Trajectory playback_truth;

  std::ostringstream md;
  md << "| frames | RSS (MiB) | keyframes | map points | bytes / keyframe | bytes / point | map (MiB) | "
        "freed "
        "KFs | freed points | waiting points | median / Y | mean / Y |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::printf("%7s %9s %6s %8s %9s %8s %8s %9s %10s %8s %8s %8s %6s\n", "frames", "RSS MiB", "KFs", "points",
              "B/KF", "B/point", "map MiB", "freed KF", "freed pts", "waiting", "med/Y", "mean/Y", "Y ms");
  lrd::System slam(cfg, params, options);
  std::vector<double> window_ms, window_y;
  cv::Mat rgb;
  const double dt = 1.0 / 30.0;
  for (int k = 0; k < frames; ++k) {
    const std::size_t i = ping_pong(static_cast<std::size_t>(k), seq.size());
    lrd::io::RgbdFrame f = seq.load_rgbd(i, cfg.camera.depth_map_factor);
    if (cfg.camera.rgb_order)
      cv::cvtColor(f.rgb, rgb, cv::COLOR_BGR2RGB);
    else
      rgb = f.rgb;
    const double stamp = seq.entry(0).timestamp + k * dt;
    playback_truth.push_back({stamp, truth_at(f.timestamp)});
    const auto t0 = std::chrono::steady_clock::now();
    const lrd::TrackResult tracked = slam.track_rgbd(rgb, f.depth, stamp);
    window_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() -
        1e3 * tracked.timing.yardstick);
    window_y.push_back(1e3 * tracked.timing.yardstick);
    if ((k + 1) % every != 0 && k + 1 != frames) continue;
    const lrd::map::MapMemory m = slam.map_memory();
    const double rss = resident_mib();
    const double per_kf =
        m.keyframes ? static_cast<double>(m.keyframe_bytes) / static_cast<double>(m.keyframes) : 0;
    const double per_pt =
        m.map_points ? static_cast<double>(m.map_point_bytes) / static_cast<double>(m.map_points) : 0;
    const double map_mib =
        static_cast<double>(m.keyframe_bytes + m.map_point_bytes + m.link_bytes) / (1024.0 * 1024.0);
    const double med = median(window_ms), y = median(window_y);
    const double mean =
        std::accumulate(window_ms.begin(), window_ms.end(), 0.0) / static_cast<double>(window_ms.size());
    std::printf("%7d %9.1f %6zu %8zu %9.0f %8.0f %8.1f %9llu %10llu %8zu %8.2f %8.2f %6.2f\n", k + 1, rss,
                m.keyframes, m.map_points, per_kf, per_pt, map_mib,
                static_cast<unsigned long long>(m.reclamation.freed_keyframes),
                static_cast<unsigned long long>(m.reclamation.freed_map_points),
                m.reclamation.waiting_map_points, med / y, mean / y, y);
    std::fflush(stdout);
    md << fmt::format(
        "| {} | {:.1f} | {} | {} | {:.0f} | {:.0f} | {:.1f} | {} | {} | {} | {:.2f} | {:.2f} |\n", k + 1, rss,
        m.keyframes, m.map_points, per_kf, per_pt, map_mib, m.reclamation.freed_keyframes,
        m.reclamation.freed_map_points, m.reclamation.waiting_map_points, med / y, mean / y);
    window_ms.clear();
    window_y.clear();
  }
  slam.shutdown();
  const lrd::MapStats stats = slam.map_stats();
  const auto ate = lrd::eval::compute_ate(playback_truth, slam.trajectory());
  std::printf(
      "RSS before the system: %.1f MiB; keyframes culled %zu; loops %zu; removed-keyframe links %zu; "
      "ATE RMSE %.2f cm over %zu frames\n",
      rss_before, stats.culled_keyframes, stats.loops, slam.map_memory().removed_keyframe_links,
      100 * ate.stats.rmse, ate.matches.size());
  if (!markdown.empty()) {
    std::ofstream out(markdown);
    out << md.str();
    std::printf("wrote %s\n", markdown.c_str());
  }
  return 0;
}
