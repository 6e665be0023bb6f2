// Scale benchmark (bench/results/scale.md): one long streamed synthetic run (the walking_long
// preset by default: 21,600 frames, laps of one room with people walking), printing every N
// frames the per-frame time (median and mean, against the interleaved Y of the same frames), the
// resident memory, the map's keyframes and points with the bytes each holds, and the local map
// tracking searched; then each loop correction (pose graph) and global BA with its latency against
// the keyframes in the map at the time; then the bars of long operation.
//
//   bench_scale [--preset walking_long] [--seed 1] [--frames 0] [--every 1000] [--mode full]
//               [--no-keyframe-culling] [--deterministic] [--pose-graph-sizes 250,500,...]
//               [--markdown FILE] [--svg FILE]
//
// Frames are rendered on the tracking thread between frames, outside the timed call: like a 30 Hz
// camera, that leaves the background threads time between frames (rendering takes ~17 ms), and
// the run needs no disk. --no-keyframe-culling grows the map to many more keyframes over the same
// room. Loops close only while the map is young (later laps track the old keyframes, which is
// what keeps the map from growing), so the pose graph at 500+ keyframes is also timed on
// essential graphs of the run's shape (edges per keyframe) at the sizes --pose-graph-sizes lists.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "bench/resident_memory.h"
#include "bench/svg_chart.h"
#include "bench/synthetic_pose_graph.h"
#include "lrd/eval/ate.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/synth/synthetic_source.h"
#include "lrd/system.h"
#include "lrd/util/yardstick.h"

namespace {

using lrd::bench::resident_mib;

using lrd::util::median_of;

struct Options {
  std::string preset = "walking_long", mode = "full", markdown, svg, config;
  std::uint64_t seed = 1;
  int frames = 0, every = 1000;
  std::vector<int> pose_graph_sizes{250, 500, 1000, 2000, 5000};
  bool deterministic = false, no_culling = false, dense = false;
};

// One frame: wall time of track_rgbd without the yardstick, the yardstick, the local map.
struct FrameSample {
  double ms = 0.0, y_ms = 0.0;
  lrd::FrameTiming timing;
  std::size_t local_keyframes = 0, local_points = 0;
  bool tracked = false;
  int inliers = 0;
};

// One printed row: the frames since the previous row.
struct WindowRow {
  int frames = 0;  // frames so far
  double median_ms = 0.0, mean_ms = 0.0, y_ms = 0.0;
  double rss_mib = 0.0;
  lrd::map::MapMemory map;
  double local_keyframes = 0.0, local_points = 0.0;  // medians over the window's tracked frames
  double inliers = 0.0;                              // median map points kept by the pose (tracked frames)
  int lost = 0;
  std::size_t loops = 0;           // closed so far
  lrd::dense::DenseStorage dense;  // the dense stage's stored clouds (--dense)
  // Means over the window, ms: extraction, mask wait, geometry, tracking, waiting for mapping.
  std::array<double, 5> stages{};
};

constexpr std::array<const char*, 5> kStageNames{"extraction", "mask wait", "geometry check", "tracking",
                                                 "waiting for mapping"};

double per(std::size_t bytes, std::size_t count) {
  return count ? static_cast<double>(bytes) / static_cast<double>(count) : 0.0;
}

WindowRow summarize_window(const std::vector<FrameSample>& all, std::size_t begin, lrd::System& slam) {
  WindowRow row;
  row.frames = static_cast<int>(all.size());
  std::vector<double> ms, y, kfs, pts, inliers;
  for (std::size_t i = begin; i < all.size(); ++i) {
    ms.push_back(all[i].ms);
    y.push_back(all[i].y_ms);
    const lrd::FrameTiming& t = all[i].timing;
    const std::array<double, 5> stage{t.extraction, t.mask_wait, t.geometry, t.tracking, t.waiting};
    for (std::size_t k = 0; k < stage.size(); ++k)
      row.stages[k] += 1e3 * stage[k] / static_cast<double>(all.size() - begin);
    if (!all[i].tracked) {
      ++row.lost;
      continue;
    }
    kfs.push_back(static_cast<double>(all[i].local_keyframes));
    pts.push_back(static_cast<double>(all[i].local_points));
    inliers.push_back(all[i].inliers);
  }
  row.median_ms = median_of(ms);
  row.mean_ms = std::accumulate(ms.begin(), ms.end(), 0.0) / static_cast<double>(ms.size());
  row.y_ms = median_of(y);
  row.local_keyframes = kfs.empty() ? 0.0 : median_of(kfs);
  row.local_points = pts.empty() ? 0.0 : median_of(pts);
  row.inliers = inliers.empty() ? 0.0 : median_of(inliers);
  row.rss_mib = resident_mib();
  row.map = slam.map_memory();
  row.loops = slam.loops().size();
  row.dense = slam.dense_storage();
  return row;
}

const char* kRowHeader =
    "| frames | median / Y | mean / Y | Y (ms) | RSS (MiB) | keyframes | map points | bytes / keyframe | "
    "bytes / point | local map: keyframes | local map: points | lost | loops |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";

std::string row_markdown(const WindowRow& r) {
  return fmt::format(
      "| {} | {:.2f} | {:.2f} | {:.2f} | {:.1f} | {} | {} | {:.0f} | {:.0f} | {:.0f} | {:.0f} | {} | {} |\n",
      r.frames, r.median_ms / r.y_ms, r.mean_ms / r.y_ms, r.y_ms, r.rss_mib, r.map.keyframes,
      r.map.map_points, per(r.map.keyframe_bytes, r.map.keyframes),
      per(r.map.map_point_bytes, r.map.map_points), r.local_keyframes, r.local_points, r.lost, r.loops);
}

// The dense stage's stored clouds against dense.max_memory_mb (--dense).
std::string dense_markdown(const std::vector<WindowRow>& rows) {
  std::string md = fmt::format("## Dense stage: stored keyframe clouds (cap {:.0f} MiB)\n\n",
                               rows.empty() ? 0.0 : rows.back().dense.max_memory_mb);
  md +=
      "| frames | clouds | points | MiB | dropped (culled keyframes) | dropped (active keyframes) |\n"
      "|---|---|---|---|---|---|\n";
  for (const WindowRow& r : rows) {
    const lrd::dense::DenseStorage& d = r.dense;
    md += fmt::format("| {} | {} | {} | {:.1f} | {} | {} |\n", r.frames, d.keyframes, d.points,
                      static_cast<double>(d.bytes) / (1024.0 * 1024.0),
                      d.evicted_keyframes - d.evicted_active, d.evicted_active);
  }
  return md + "\n";
}

std::string stages_markdown(const std::vector<WindowRow>& rows) {
  std::string md = "| frames |";
  for (const char* name : kStageNames) md += fmt::format(" {} |", name);
  md += " pose inliers (median) |\n|---|---|---|---|---|---|---|\n";
  for (const WindowRow& r : rows) {
    md += fmt::format("| {} |", r.frames);
    for (const double ms : r.stages) md += fmt::format(" {:.3f} |", ms / r.y_ms);
    md += fmt::format(" {:.0f} |\n", r.inliers);
  }
  return md;
}

// Median frame time over Y's median, frames [begin, end) of the run.
double ratio_over(const std::vector<FrameSample>& all, std::size_t begin, std::size_t end) {
  std::vector<double> ms, y;
  for (std::size_t i = begin; i < std::min(end, all.size()); ++i) {
    ms.push_back(all[i].ms);
    y.push_back(all[i].y_ms);
  }
  return ms.empty() ? 0.0 : median_of(ms) / median_of(y);
}

std::string loops_markdown(const std::vector<lrd::loop::LoopEvent>& loops,
                           const std::vector<lrd::loop::GlobalBaRun>& runs) {
  std::string md =
      "| frame | keyframe - loop keyframe | map keyframes | essential-graph edges | detection (ms) | "
      "correction incl. pose graph (ms) | moved (m) | global BA: keyframes | points | seconds |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& e : loops) {
    std::string ba = "| - | - | - |";
    for (const auto& r : runs)
      if (r.loop_keyframe_id == e.keyframe_id)
        ba = fmt::format("| {} | {} | {:.2f}{} |", r.keyframes, r.points, r.seconds,
                         r.aborted ? " (aborted)" : (r.implausible ? " (not merged)" : ""));
    md += fmt::format("| {} | {} - {} | {} | {} | {:.1f} | {:.1f} | {:.3f} {}\n", e.frame_id, e.keyframe_id,
                      e.loop_keyframe_id, e.keyframes, e.pose_graph_edges, 1e3 * e.detection_seconds,
                      1e3 * e.correction_seconds, e.correction_m, ba);
  }
  return md;
}

double all_y(const std::vector<FrameSample>& samples) {
  std::vector<double> y;
  for (const FrameSample& s : samples) y.push_back(s.y_ms);
  return median_of(y);
}

// Essential graphs shaped like the run's (its loops' edges per keyframe), timed at each size.
std::string pose_graph_markdown(const std::vector<lrd::loop::LoopEvent>& loops, const std::vector<int>& sizes,
                                double y_ms) {
  double edges = 0.0, keyframes = 0.0;
  for (const auto& e : loops) {
    edges += static_cast<double>(e.pose_graph_edges);
    keyframes += static_cast<double>(e.keyframes);
  }
  const double per_keyframe = keyframes > 0 ? edges / keyframes : 4.5;
  std::string md = fmt::format(
      "## Pose graph at scale: essential graphs of {:.1f} edges a keyframe (the run's loops), 30 keyframes a "
      "lap, 20 iterations\n\n"
      "| keyframes | edges | optimize_pose_graph (ms) | / Y | cost before | cost after | drift before (m) | "
      "after (m) |\n|---|---|---|---|---|---|---|---|\n",
      per_keyframe);
  for (const int n : sizes) {
    if (n < 31) continue;
    const lrd::bench::PoseGraphTiming t = lrd::bench::time_synthetic_pose_graph(n, per_keyframe);
    md += fmt::format("| {} | {} | {:.0f} | {:.0f} | {:.3g} | {:.3g} | {:.3f} | {:.3f} |\n", t.keyframes,
                      t.edges, 1e3 * t.seconds, 1e3 * t.seconds / y_ms, t.initial_cost, t.final_cost,
                      t.drift_before_m, t.error_after_m);
  }
  return md;
}

std::string plot(const std::vector<WindowRow>& rows, const std::vector<lrd::loop::LoopEvent>& loops) {
  lrd::bench::ChartSeries med{"median / Y", "#1f77b4", {}, {}}, mean{"mean / Y", "#ff7f0e", {}, {}};
  lrd::bench::ChartSeries kfs{"keyframes", "#2ca02c", {}, {}},
      local{"local-map keyframes", "#9467bd", {}, {}};
  lrd::bench::ChartSeries rss{"resident MiB", "#d62728", {}, {}}, pts{"map points / 100", "#8c564b", {}, {}};
  lrd::bench::ChartSeries corr{"loop correction ms", "#e377c2", {}, {}, true};
  auto add = [](lrd::bench::ChartSeries& s, double x, double y) {
    s.x.push_back(x);
    s.y.push_back(y);
  };
  for (const WindowRow& r : rows) {
    const double x = r.frames;
    add(med, x, r.median_ms / r.y_ms);
    add(mean, x, r.mean_ms / r.y_ms);
    add(kfs, x, static_cast<double>(r.map.keyframes));
    add(local, x, r.local_keyframes);
    add(rss, x, r.rss_mib);
    add(pts, x, static_cast<double>(r.map.map_points) / 100.0);
  }
  for (const auto& e : loops) add(corr, static_cast<double>(e.frame_id), 1e3 * e.correction_seconds);
  std::vector<lrd::bench::ChartPanel> panels{{"time per frame / Y (per 1,000-frame window)", {med, mean}},
                                             {"map size", {kfs, local, pts}},
                                             {"memory", {rss}}};
  if (!corr.x.empty()) panels.push_back({"loop correction latency (ms), at its frame", {corr}});
  return lrd::bench::svg_chart(panels, 0.0, rows.empty() ? 1.0 : rows.back().frames, "frame");
}

// The run itself: every frame rendered, then tracked and timed; a row every `every` frames.
struct RunData {
  std::vector<FrameSample> samples;
  std::vector<WindowRow> rows;
  std::size_t lap2_frame = 0, keyframes_after_lap2 = 0;
  std::string md;
};

RunData track_all(lrd::System& slam, const lrd::synth::SyntheticSource& source,
                  const lrd::config::Config& cfg, int every) {
  RunData run;
  const std::size_t n = source.size();
  run.samples.reserve(n);
  run.md = fmt::format("## Every {} frames\n\n{}", every, kRowHeader);
  std::printf("%s", kRowHeader);
  run.lap2_frame =
      static_cast<std::size_t>(2 * lrd::synth::CameraMotion::kTourLap * source.sequence().camera().fps);
  cv::Mat rgb;
  for (std::size_t i = 0; i < n; ++i) {
    lrd::io::RgbdFrame f = source.load_rgbd(i, 1.0);
    if (cfg.camera.rgb_order)
      cv::cvtColor(f.rgb, rgb, cv::COLOR_BGR2RGB);
    else
      rgb = f.rgb;
    const auto t0 = std::chrono::steady_clock::now();
    const lrd::TrackResult r = slam.track_rgbd(rgb, f.depth, source.entry(i).timestamp);
    const double wall =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    run.samples.push_back({wall - 1e3 * r.timing.yardstick, 1e3 * r.timing.yardstick, r.timing,
                           r.local_keyframes, r.local_points, r.state == lrd::TrackingState::Ok, r.inliers});
    if (i + 1 == run.lap2_frame) run.keyframes_after_lap2 = slam.map_stats().keyframes;
    if ((i + 1) % static_cast<std::size_t>(every) != 0 && i + 1 != n) continue;
    const std::size_t begin = run.rows.empty() ? 0 : static_cast<std::size_t>(run.rows.back().frames);
    run.rows.push_back(summarize_window(run.samples, begin, slam));
    const std::string line = row_markdown(run.rows.back());
    std::printf("%s", line.c_str());
    std::fflush(stdout);
    run.md += line;
  }
  return run;
}

// The bars of long operation: late frames within 10 % of early ones, against Y; a pose-graph
// correction at 500+ keyframes under 1 s. Whether the map grows with the space explored, not
// with the time spent: keyframes after lap 2 and at the end.
std::string summary_markdown(const RunData& run, const lrd::MapStats& stats,
                             const std::vector<lrd::loop::LoopEvent>& loops,
                             const lrd::eval::AteResult& ate) {
  const std::size_t n = run.samples.size();
  const bool long_run = n >= 20000;
  const std::size_t e0 = long_run ? 1000 : n / 20, e1 = long_run ? 5000 : n / 4;
  const std::size_t l0 = long_run ? 15000 : 3 * n / 4, l1 = long_run ? 20000 : n;
  const double early = ratio_over(run.samples, e0, e1), late = ratio_over(run.samples, l0, l1);
  double slowest_large = -1.0;
  for (const auto& e : loops)
    if (e.keyframes >= 500) slowest_large = std::max(slowest_large, e.correction_seconds);
  return fmt::format(
      "\n## Summary\n\n"
      "- per-frame time, median / Y: frames {}-{} {:.2f}, frames {}-{} {:.2f}: {:+.1f} % (bar: within 10 %)\n"
      "- keyframes after lap 2 (frame {}): {}; at the end: {} ({} culled); map points at the end: {}\n"
      "- slowest loop correction at 500+ keyframes: {} (bar: under 1 s)\n"
      "- ATE RMSE {:.2f} cm over {} frames; frames not tracked: {}\n",
      e0, e1, early, l0, l1, late, 100.0 * (late / early - 1.0), run.lap2_frame, run.keyframes_after_lap2,
      stats.keyframes, stats.culled_keyframes, stats.map_points,
      slowest_large < 0 ? std::string("none (no loop closed at 500+ keyframes)")
                        : fmt::format("{:.0f} ms", 1e3 * slowest_large),
      100.0 * ate.stats.rmse, ate.matches.size(),
      std::count_if(run.samples.begin(), run.samples.end(), [](const FrameSample& s) { return !s.tracked; }));
}

int run_benchmark(const Options& opt) {
  lrd::synth::SynthOptions so;
  so.preset = opt.preset;
  so.seed = opt.seed;
  so.frames = opt.frames > 0 ? opt.frames : -1;
  const auto source = std::make_shared<const lrd::synth::SyntheticSource>(so);
  lrd::runner::RunOptions ro;
  ro.source = source;
  ro.mode = opt.mode;
  ro.deterministic = opt.deterministic;
  ro.dense = opt.dense;
  if (!opt.config.empty()) ro.config = opt.config;
  const lrd::config::Config cfg = lrd::runner::resolve_config(ro);
  lrd::SystemParams params = lrd::runner::configure_system(ro, cfg);
  if (opt.no_culling) params.mapping.keyframe_culling = false;
  lrd::SystemOptions options;
  options.deterministic = opt.deterministic;
  options.yardstick = true;  // Y timed in the tracking thread beside each frame's extraction
  std::printf(
      "bench_scale: %s seed %llu, %zu frames rendered between frames (untimed), mode %s, %s%s; ratios divide "
      "by each window's interleaved Y (OpenCV ORB in the tracking thread on the same frames)\n",
      opt.preset.c_str(), static_cast<unsigned long long>(opt.seed), source->size(), opt.mode.c_str(),
      opt.deterministic ? "deterministic" : "threaded", opt.no_culling ? ", keyframe culling off" : "");
  std::printf("RSS before the system: %.1f MiB\n", resident_mib());

  lrd::System slam(cfg, params, options);
  RunData run = track_all(slam, *source, cfg, opt.every);
  slam.shutdown();
  const lrd::MapStats stats = slam.map_stats();
  const auto loops = slam.loops();
  const std::string loop_md = loops_markdown(loops, slam.global_ba_runs());
  const std::string stage_md = "## Stages: mean per frame / Y, each window\n\n" + stages_markdown(run.rows) +
                               (opt.dense ? "\n" + dense_markdown(run.rows) : "");
  const std::string graph_md = pose_graph_markdown(loops, opt.pose_graph_sizes, all_y(run.samples));
  const std::string summary =
      summary_markdown(run, stats, loops, lrd::eval::compute_ate(*source->ground_truth(), slam.trajectory()));
  const std::string rest =
      fmt::format("\n## Loops ({} closed, {} rejected) and global BA\n\n{}\n{}\n{}{}", loops.size(),
                  stats.rejected_loops, loop_md, stage_md, graph_md, summary);
  std::printf("%s", rest.c_str());
  if (!opt.markdown.empty()) {
    std::ofstream(opt.markdown) << run.md << rest;
    std::printf("wrote %s\n", opt.markdown.c_str());
  }
  if (!opt.svg.empty()) {
    std::ofstream(opt.svg) << plot(run.rows, loops);
    std::printf("wrote %s\n", opt.svg.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Scale benchmark: per-frame time, memory, map and loop latency over a long streamed run"};
  Options opt;
  app.add_option("--preset", opt.preset, "Synthetic preset, rendered frame by frame");
  app.add_option("--seed", opt.seed, "The preset's seed");
  app.add_option("--frames", opt.frames, "Frames (0: the preset's length)")->check(CLI::NonNegativeNumber);
  app.add_option("--every", opt.every, "A row every N frames")->check(CLI::PositiveNumber);
  app.add_option("--mode", opt.mode, "Dynamic-scene mode");
  app.add_option("--config", opt.config, "An lrd-slam YAML config (e.g. tracking settings)");
  app.add_flag("--no-keyframe-culling", opt.no_culling, "Keep every keyframe (a larger pose graph)");
  app.add_flag("--dense", opt.dense,
               "With the dense stage (its stored clouds per window; dense.max_memory_mb)");
  app.add_flag("--deterministic", opt.deterministic, "Lock-step local mapping");
  app.add_option("--pose-graph-sizes", opt.pose_graph_sizes,
                 "Keyframes of the essential graphs timed after the run (shaped like the run's)")
      ->delimiter(',');
  app.add_option("--markdown", opt.markdown, "Also write the tables as Markdown to this file");
  app.add_option("--svg", opt.svg, "Write a plot of the rows and loops to this SVG file");
  CLI11_PARSE(app, argc, argv);
  try {
    return run_benchmark(opt);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_scale: error: %s\n", e.what());
    return 1;
  }
}
