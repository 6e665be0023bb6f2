// `lrdslam run`: SLAM over a TUM-layout sequence folder, a TUM-style rosbag or a synthetic
// sequence rendered on the fly; trajectories,
// per-frame timings and a summary into --out, and ATE/RPE when the input has ground truth.
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "app/bag_input.h"
#include "app/commands.h"
#include "app/realism_options.h"
#include "lrd/report/html_page.h"
#include "lrd/report/run_data.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/synth/camera_motion.h"
#include "lrd/synth/synthetic_source.h"
#include "lrd/util/error.h"

namespace lrd::app {
namespace {

using runner::LocalizationLatency;

// SIGINT / SIGTERM: the first stops reading frames (the run then writes its outputs and exits 130),
// a second exits at once. Only async-signal-safe calls in the handler.
std::atomic<bool> interrupt_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_interrupt(int /*signal*/) {
  const int saved_errno = errno;  // write() may change it under the interrupted thread
  if (interrupt_requested.exchange(true)) _exit(130);
  constexpr char kMessage[] = "\ninterrupt: finishing and writing the outputs (again to quit at once)\n";
  [[maybe_unused]] const auto n = write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
  errno = saved_errno;
}

void handle_interrupts() {
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  action.sa_flags = SA_RESTART;  // the other threads' reads and writes go on
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

struct RunCli {
  std::string sequence, settings, preset, config, out, mode, segmenter, segmenter_model, save_masks,
      save_repaired;
  bool dense = false;
  bool occupancy = false;
  bool no_loop_closing = false;
  std::string vocabulary;
  bool realtime = false;
  bool preload = false;
  bool yardstick = false;
  bool deterministic = false;
  bool quiet = false;
  bool report = false;
  std::size_t max_frames = 0;
  std::string load_map, save_map;
  double autosave = 0.0;
  bool localization_only = false;
  BagCli bag;
  // --synth: frames rendered on the decoding thread, nothing written but the outputs.
  std::string synth;
  synth::SynthOptions synth_options;
  RealismOptions realism;
};

void print_dense(const runner::DenseReport& d) {
  std::printf(
      "dense map: %zu points (merged in %.2f s); repair: %zu keyframes, %.1f %% of %zu dynamic pixels filled",
      d.points, d.assemble_seconds, d.repair.keyframes, 100.0 * d.repair.fill_ratio(),
      d.repair.dynamic_pixels);
  if (d.repair_median_depth_error)
    std::printf(", median depth error %.1f mm vs the static scene", 1e3 * *d.repair_median_depth_error);
  std::printf("\n");
  if (d.map) std::printf("dense map vs scene: %s\n", eval::describe(*d.map).c_str());
}

void print_occupancy(const runner::OccupancyReport& r) {
  std::printf(
      "occupancy: %zu occupied, %zu free voxels at %.0f cm (built in %.2f s); floor at %.2f m; 2-D grid "
      "%dx%d: "
      "%zu occupied, %zu free cells\n",
      r.occupied_voxels, r.free_voxels, 100.0 * r.resolution, r.build_seconds, r.floor_height, r.grid_width,
      r.grid_height, r.grid_occupied, r.grid_free);
  if (r.accuracy) std::printf("occupancy vs scene: %s\n", eval::describe(*r.accuracy).c_str());
}

void print_report(const runner::RunReport& r) {
  std::printf("camera: %s\n", r.camera_source.c_str());
  std::printf("frames: %zu  tracked: %zu  lost: %zu  not initialized: %zu", r.frames, r.tracked, r.lost,
              r.not_initialized);
  if (r.loaded_map)
    std::printf("  not localized: %zu\nloaded map: %s (%zu keyframes, %zu map points)%s", r.not_localized,
                r.loaded_map->string().c_str(), r.map.loaded_keyframes, r.map.loaded_map_points,
                r.localization_only ? ", localization only" : "");
  std::printf("\n");
  if (r.loaded_map) {
    const LocalizationLatency& l = r.localization;
    std::printf("localized in the loaded map at frame %s",
                l.first_localized_frame ? std::to_string(*l.first_localized_frame).c_str() : "- (never)");
    if (l.first_view_frame)
      std::printf(" (its first view of the map: frame %zu, %zu frames before)", *l.first_view_frame,
                  l.frames().value_or(0));
    std::printf("\n");
  }
  std::printf("map: %zu keyframes (%zu culled), %zu map points, %zu local BAs\n", r.map.keyframes,
              r.map.culled_keyframes, r.map.map_points, r.map.bundle_adjustments);
  std::printf("mode: %s  segmentation: %s\n", r.mode.c_str(), r.segmentation.c_str());
  std::printf(
      "place recognition: %s; loop closing %s; %zu loops closed (%d rejected), %d relocalizations, %d global "
      "BAs\n",
      r.vocabulary.empty() ? "off (no vocabulary)" : r.vocabulary.c_str(), r.loop_closing ? "on" : "off",
      r.loops.size(), r.map.rejected_loops, r.map.relocalizations, r.map.global_bundle_adjustments);
  for (const loop::LoopEvent& e : r.loops)
    std::printf("  loop: frame %llu (keyframe %llu) -> keyframe %llu, %d inliers, corrected by %.3f m\n",
                static_cast<unsigned long long>(e.frame_id), static_cast<unsigned long long>(e.keyframe_id),
                static_cast<unsigned long long>(e.loop_keyframe_id), e.inliers, e.correction_m);
  std::printf("time per frame (ms, without decoding): median %.1f  mean %.1f\n", r.total.median_ms,
              r.total.mean_ms);
  std::printf(
      "  extraction %.1f / %.1f  tracking %.1f / %.1f  waiting %.1f / %.1f  mapping %.1f / %.1f "
      "(median / mean)\n",
      r.extraction.median_ms, r.extraction.mean_ms, r.tracking.median_ms, r.tracking.mean_ms,
      r.waiting.median_ms, r.waiting.mean_ms, r.mapping.median_ms, r.mapping.mean_ms);
  if (r.segmentation != "none" || r.mode == "geometric")
    std::printf(
        "  segmentation %.1f (own thread)  mask wait %.1f  geometry check %.1f (median); mean mask age %.2f "
        "frames, %zu frames without a mask\n",
        r.segmentation_time.median_ms, r.mask_wait.median_ms, r.geometry.median_ms, r.mean_mask_age,
        r.frames_without_mask);
  if (r.flags) {
    const auto& f = *r.flags;
    std::string classes;
    if (f.moved_object > 0) classes += fmt::format("  (moved objects: {:.3f})", f.moved_object_recall());
    if (f.balloon > 0) classes += fmt::format("  (balloons: {:.3f})", f.balloon_recall());
    std::printf("dynamic keypoint flags vs ground-truth masks (%zu frames): precision %.3f  recall %.3f%s\n",
                f.frames, f.precision(), f.recall(), classes.c_str());
  }
  std::printf("throughput with I/O: %.1f frames/s (decoding %.1f s on its own thread, %.1f s waited for)\n",
              r.wall_seconds > 0 ? static_cast<double>(r.frames) / r.wall_seconds : 0.0, r.decode_seconds,
              r.io_wait_seconds);
  if (r.has_ground_truth) {
    std::printf("ATE RMSE: %.4f m  (mean %.4f, median %.4f, max %.4f; %zu pairs)\n", r.ate_rmse, r.ate_mean,
                r.ate_median, r.ate_max, r.ate_pairs);
    std::printf("RPE RMSE: %.4f m/s  %.3f deg/s\n", r.rpe_trans_rmse, r.rpe_rot_rmse);
  }
  if (r.dense) print_dense(*r.dense);
  if (r.occupancy) print_occupancy(*r.occupancy);
  std::string written;
  for (const char* f : {"CameraTrajectory.txt", "KeyFrameTrajectory.txt", "groundtruth.txt",
                        "track_times.txt", "summary.json", "dense_map.ply", "dense_map.png", "occupancy.bt",
                        "occupancy_2d.pgm", "occupancy_2d.yaml", "occupancy_2d.png"})
    if (std::filesystem::exists(r.out / f)) written += (written.empty() ? "" : ", ") + std::string(f);
  std::printf("wrote %s/{%s}\n", r.out.string().c_str(), written.c_str());
  if (r.saved_map) std::printf("wrote map %s\n", r.saved_map->string().c_str());
}

void write_report(const std::filesystem::path& out, const std::string& sequence) {
  report::RunSources sources{out, std::nullopt};
  if (!sequence.empty()) sources.sequence = sequence;
  report::write_html_report(out / "report.html", report::collect_run_data(sources));
  std::printf("wrote %s\n", (out / "report.html").string().c_str());
}

}  // namespace

void register_run_command(CLI::App& app) {
  auto cli = std::make_shared<RunCli>();
  CLI::App* cmd = app.add_subcommand(
      "run", "Run SLAM on a TUM-layout RGB-D sequence folder, a rosbag or a synthetic preset");
  auto* sequence = cmd->add_option("--sequence", cli->sequence,
                                   "Sequence folder (rgb.txt + depth.txt, or associations.txt)");
  auto* bag = cmd->add_option(
      "--bag", cli->bag.bag,
      "Read the frames from a bag in the TUM RGB-D layout instead: a ROS 1 .bag, or a ROS 2 bag "
      "(.mcap, .db3, or a rosbag2 folder); no ROS running or installed for ROS 2");
  sequence->excludes(bag);
  auto* synth =
      cmd->add_option("--synth", cli->synth,
                      "Render a synthetic preset's frames on the fly instead (`lrdslam synth --list`): no "
                      "sequence on disk; OUT/groundtruth.txt gets its ground truth")
          ->excludes(sequence)
          ->excludes(bag);
  cmd->add_option("--seed", cli->synth_options.seed, "With --synth: the sequence's seed (as `synth --seed`)")
      ->needs(synth)
      ->capture_default_str();
  cmd->add_option("--session", cli->synth_options.session,
                  "With --synth: the map-file session (as `synth --session`)")
      ->needs(synth)
      ->check(CLI::Range(1, synth::CameraMotion::kMaxSession))
      ->capture_default_str();
  cli->realism.add_to(cmd, synth);
  cmd->add_option("--frames", cli->synth_options.frames,
                  "With --synth: frames to render (default: the preset's length; a prefix of it)")
      ->needs(synth)
      ->check(CLI::PositiveNumber);
  cmd->add_option("--rgb-topic", cli->bag.rgb_topic, "With --bag: colour images (sensor_msgs/Image)")
      ->capture_default_str();
  cmd->add_option("--depth-topic", cli->bag.depth_topic,
                  "With --bag: depth images (sensor_msgs/Image, 32FC1 metres or 16UC1 millimetres)")
      ->capture_default_str();
  cmd->add_option("--camera-info-topic", cli->bag.camera_info_topic,
                  "With --bag: the camera when no --settings/--preset/config camera is given")
      ->capture_default_str();
  cmd->add_option("--gt-from-tf", cli->bag.gt_from_tf,
                  "With --bag: ground truth = CHILD's pose in PARENT on /tf, e.g. /world:/kinect (TUM bags)");
  auto* settings = cmd->add_option("--settings", cli->settings, "ORB-SLAM2/3 settings file for the camera");
  cmd->add_option("--preset", cli->preset,
                  "Camera preset: tum1, tum2, tum3 (TUM RGB-D), bonn (Bonn RGB-D Dynamic)")
      ->excludes(settings);
  cmd->add_option("--config", cli->config, "lrd-slam YAML config (see config/default.yaml)");
  cmd->add_option("--out", cli->out, "Output folder (default: the config's output.dir, \"output\")");
  cmd->add_flag("--deterministic", cli->deterministic,
                "Local mapping in lock-step after each keyframe: identical input gives identical bytes");
  cmd->add_option(
      "--mode", cli->mode,
      "Dynamic-scene mode: static (ORB-SLAM2), semantic (LRD-SLAM P), geometric, full (LRD-SLAM C); "
      "default: the config's dynamic.mode");
  cmd->add_option(
      "--segmenter", cli->segmenter,
      "Segmentation: none; gt-masks (synthetic ground truth, people), gt-masks-all; networks: fnet "
      "(ours, for the synthetic benchmark), selfie-landscape (real people; the default for real data), "
      "selfie, espnetv2-voc (needs --segmenter-model). Default: the config's segmentation section, "
      "or for semantic/full without one: fnet on synthetic sequences, selfie-landscape otherwise");
  cmd->add_option("--segmenter-model", cli->segmenter_model,
                  "The segmenter preset's ONNX file (overrides its default)");
  cmd->add_option("--save-masks", cli->save_masks,
                  "Write each frame's dynamic mask (PNG, named like its colour image) to this folder");
  cmd->add_flag("--dense", cli->dense,
                "Dense map: background repair of the keyframes and a coloured point cloud (dense_map.ply, "
                "dense_map.png)");
  cmd->add_flag("--occupancy", cli->occupancy,
                "Occupancy map for navigation (implies --dense): an OctoMap (occupancy.bt) and a 2-D grid in "
                "ROS map_server format (occupancy_2d.pgm/.yaml, occupancy_2d.png with the path). --dense "
                "writes them too unless the config's occupancy.enabled is false");
  cmd->add_option("--save-repaired", cli->save_repaired,
                  "Write each keyframe's repaired colour and depth (with the originals) to this folder");
  cmd->add_option("--max-frames", cli->max_frames, "Stop after this many frames (0: all)");
  cmd->add_flag(
      "--realtime", cli->realtime,
      "Feed frames at their timestamps' pace, like a live camera (default: as fast as they are tracked)");
  cmd->add_flag(
      "--preload", cli->preload,
      "Decode every frame before tracking starts (~2 MB a frame): per-frame times without a decoding "
      "thread beside them, as ORB-SLAM2 measured (the benchmarks do this)");
  cmd->add_flag("--yardstick", cli->yardstick,
                "Time OpenCV's ORB (1000/1.2/8) on every frame beside the extraction: the yardstick Y in "
                "summary.json's per_frame.yardstick, measured in the same run (sweeps and benchmarks)");
  cmd->add_flag("--no-loop-closing", cli->no_loop_closing,
                "Switch loop closing off (ablations); relocalization stays");
  cmd->add_option("--vocabulary", cli->vocabulary,
                  "Bag-of-words vocabulary (lrdslam vocab train); default: the shipped vocab/orb_vocab.lrdv");
  cmd->add_option("--load-map", cli->load_map,
                  "Start from a map saved by --save-map (.lrdmap): the first frames relocalize against it, "
                  "the trajectory is in its frame; without --localization-only the run extends it");
  cmd->add_flag("--localization-only", cli->localization_only,
                "With --load-map: track against the loaded map without adding keyframes or map points");
  cmd->add_option("--save-map", cli->save_map,
                  "Write the final sparse map (keyframes, map points, graphs) to this .lrdmap file");
  cmd->add_option(
         "--autosave", cli->autosave,
         "With --save-map: write the map there and the trajectory so far to OUT/CameraTrajectory.txt "
         "every SECONDS and after each loop closure, so that a run killed hard leaves its last "
         "complete save (restart with --load-map on it)")
      ->type_name("SECONDS");
  cmd->add_flag("--quiet", cli->quiet, "No progress bar");
  cmd->add_flag("--report", cli->report,
                "Write OUT/report.html at the end: one self-contained page (as `lrdslam report OUT`)");
  cmd->callback([cli] {
    const int inputs = !cli->sequence.empty() + !cli->bag.bag.empty() + !cli->synth.empty();
    if (inputs != 1)
      throw Error("run: give the frames as --sequence FOLDER, --bag FILE.bag or --synth PRESET");
    runner::RunOptions o;
    o.sequence = cli->sequence;
    if (!cli->bag.bag.empty()) o.source = open_bag(cli->bag);
    if (!cli->synth.empty()) {
      cli->synth_options.preset = cli->synth;
      cli->synth_options.realism = cli->realism.params();
      o.source = std::make_shared<const synth::SyntheticSource>(cli->synth_options);
    }
    if (!cli->settings.empty()) o.settings = cli->settings;
    if (!cli->preset.empty()) o.preset = cli->preset;
    if (!cli->config.empty()) o.config = cli->config;
    o.out = cli->out;
    o.deterministic = cli->deterministic;
    o.max_frames = cli->max_frames;
    if (!cli->mode.empty()) o.mode = cli->mode;
    if (!cli->segmenter.empty()) o.segmenter = cli->segmenter;
    if (!cli->segmenter_model.empty()) o.segmenter_model = cli->segmenter_model;
    if (!cli->save_masks.empty()) o.save_masks = cli->save_masks;
    if (!cli->save_repaired.empty()) o.save_repaired = cli->save_repaired;
    o.dense = cli->dense;
    if (cli->occupancy) o.occupancy = true;
    o.no_loop_closing = cli->no_loop_closing;
    if (!cli->vocabulary.empty()) o.vocabulary = cli->vocabulary;
    if (!cli->load_map.empty()) o.load_map = cli->load_map;
    if (!cli->save_map.empty()) o.save_map = cli->save_map;
    o.localization_only = cli->localization_only;
    o.autosave_seconds = cli->autosave;
    o.realtime = cli->realtime;
    o.preload = cli->preload;
    o.yardstick = cli->yardstick;
    o.progress = !cli->quiet;
    o.report_frames = cli->report;
    if (cli->report) report::check_report_assets();  // a missing asset stops the run before it starts
    o.interrupt = &interrupt_requested;
    handle_interrupts();
    const runner::RunReport r = runner::run_sequence(o);
    print_report(r);
    if (cli->report) write_report(r.out, cli->sequence);
    if (r.interrupted) {
      std::fprintf(stderr, "interrupted after %zu frames\n", r.frames);
      std::fflush(stdout);
      std::exit(130);
    }
  });
}

}  // namespace lrd::app
