#include "lrd/runner/sequence_runner.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "lrd/autosave/autosaver.h"
#include "lrd/config/orbslam_settings.h"
#include "lrd/dynamic/dynamic_params.h"
#include "lrd/eval/ate.h"
#include "lrd/eval/rpe.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/io/frame_prefetcher.h"
#include "lrd/io/trajectory.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/runner/dense_evaluation.h"
#include "lrd/runner/map_outputs.h"
#include "lrd/runner/progress_bar.h"
#include "lrd/runner/run_recorder.h"
#include "lrd/runner/sample_frames.h"
#include "lrd/segmentation/onnx_presets.h"
#include "lrd/util/error.h"
#include "lrd/util/yardstick.h"

namespace lrd::runner {

namespace fs = std::filesystem;

namespace {

// The frames through the system, as fast as they are tracked (or at the camera's pace).
// Returns false when interrupted.
// `during_saves` gets the index of each frame tracked while an autosave was under way.
bool track_frames(System& slam, io::FramePrefetcher& frames, const RunOptions& o, const io::FrameSource& seq,
                  const camera::PinholeCamera& camera, const std::string& camera_source,
                  std::chrono::steady_clock::time_point wall0, const autosave::Autosaver* autosaver,
                  std::vector<std::size_t>& during_saves) {
  cv::Mat rgb;
  std::optional<double> first_stamp;
  const auto interrupted = [&o] { return o.interrupt != nullptr && o.interrupt->load(); };
  while (!interrupted()) {
    auto f = frames.next();
    if (!f) return true;
    if (o.realtime) {
      // A live camera: frame k is not there before its timestamp's offset from the first frame.
      if (!first_stamp) first_stamp = f->timestamp;
      std::this_thread::sleep_until(wall0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                std::chrono::duration<double>(f->timestamp - *first_stamp)));
    }
    // The image against the calibration: the error names both files.
    if (f->rgb.cols != camera.width || f->rgb.rows != camera.height)
      throw file_error(seq.describe(f->index),
                       fmt::format("image is {}x{}, the camera ({}) is {}x{}", f->rgb.cols, f->rgb.rows,
                                   camera_source, camera.width, camera.height));
    // The loader gives BGR; the system expects the camera's colour order.
    if (camera.rgb_order)
      cv::cvtColor(f->rgb, rgb, cv::COLOR_BGR2RGB);
    else
      rgb = f->rgb;
    const std::size_t begun = autosaver != nullptr ? autosaver->saves_begun() : 0;
    const bool saving = autosaver != nullptr && autosaver->saving();
    (void)slam.track_rgbd(rgb, f->depth, f->timestamp);
    if (autosaver != nullptr && (saving || autosaver->saving() || autosaver->saves_begun() != begun))
      during_saves.push_back(f->index);
  }
  return false;
}

AutosaveReport autosave_report(double period, const autosave::AutosaveStats& stats,
                               const std::vector<FrameLog>& log, std::vector<std::size_t> during_saves) {
  AutosaveReport r;
  r.period_seconds = period;
  r.saves = stats.saves;
  r.loop_saves = stats.loop_saves;
  r.failures = stats.failures;
  // Median and maximum, ms (both 0 without saves).
  const auto summarize = [](const std::vector<double>& seconds, double& median_ms, double& max_ms) {
    if (seconds.empty()) return;
    median_ms = 1e3 * util::median_of(seconds);
    max_ms = 1e3 * *std::max_element(seconds.begin(), seconds.end());
  };
  summarize(stats.save_seconds, r.save_median_ms, r.save_max_ms);
  summarize(stats.lock_seconds, r.lock_median_ms, r.lock_max_ms);
  std::sort(during_saves.begin(), during_saves.end());
  std::vector<double> during, otherwise;
  for (const FrameLog& f : log)
    (std::binary_search(during_saves.begin(), during_saves.end(), f.index) ? during : otherwise)
        .push_back(1e3 * f.timing.total());
  r.frames_during_saves = during.size();
  r.frame_indices_during_saves = std::move(during_saves);
  if (!during.empty()) r.total_median_ms_during_saves = util::median_of(during);
  if (!otherwise.empty()) r.total_median_ms_otherwise = util::median_of(otherwise);
  return r;
}

// Trajectories, ATE/RPE against the sequence's ground truth, the dense map, summary.json.
void evaluate(RunReport& report, const System& slam, const RunOptions& o, const io::FrameSource& seq,
              const config::Config& cfg, const SystemParams& params,
              const std::shared_ptr<RepairRecorder>& repairs,
              const std::vector<Eigen::Vector3d>& loaded_points) {
  summarize_log(report);
  report.map = slam.map_stats();
  report.loops = slam.loops();
  const io::Trajectory trajectory = slam.trajectory();
  if (cfg.output.save_trajectory) io::write_trajectory_tum(o.out / "CameraTrajectory.txt", trajectory);
  if (cfg.output.save_keyframes) slam.save_keyframe_trajectory_tum(o.out / "KeyFrameTrajectory.txt");
  write_track_times(o.out / "track_times.txt", report.log);
  const std::optional<io::Trajectory> ground_truth =
      trajectory.size() >= 2 ? seq.ground_truth() : std::nullopt;
  if (ground_truth) {
    const io::Trajectory& gt = *ground_truth;
    // A source without a folder (a bag's /tf, a rendered sequence) leaves its ground truth beside
    // the trajectory, so the run folder can be evaluated and reported on its own.
    if (!seq.folder()) io::write_trajectory_tum(o.out / "groundtruth.txt", gt);
    try {
      const eval::AteResult ate = eval::compute_ate(gt, trajectory);
      const eval::RpeResult rpe = eval::compute_rpe(gt, trajectory, 1.0);
      report.has_ground_truth = true;
      report.ate_rmse = ate.stats.rmse;
      report.ate_mean = ate.stats.mean;
      report.ate_median = ate.stats.median;
      report.ate_max = ate.stats.max;
      report.ate_pairs = ate.stats.count;
      report.rpe_trans_rmse = rpe.trans.rmse;
      report.rpe_rot_rmse = rpe.rot.rmse;
      report.ate = ate.stats;
      report.rpe_trans = rpe.trans;
      report.rpe_rot = rpe.rot;
      if (report.loaded_map) {
        std::vector<TrackingState> states;
        for (const FrameLog& f : report.log) states.push_back(f.state);
        report.localization = localization_latency(loaded_points, states, seq, gt, ate.alignment, cfg.camera);
      }
    } catch (const Error& e) {
      spdlog::warn("no ATE/RPE: {} vs {}: {}", (o.out / "CameraTrajectory.txt").string(),
                   seq.ground_truth_origin(), e.what());
    }
  }
  if (slam.dense_enabled()) finish_maps(report, slam, *repairs, o, trajectory, cfg.camera, params);
  write_summary_json(o.out / "summary.json", report);
}

}  // namespace

RunReport run_sequence(const RunOptions& options) {
  RunReport report;
  // Configure.
  const config::Config cfg = resolve_config(options, &report.camera_source);
  RunOptions o = options;
  if (o.out.empty()) o.out = cfg.output.dir;
  report.out = o.out;
  const SystemParams params = configure_system(o, cfg);
  if (o.localization_only && !o.load_map)
    throw Error("run: --localization-only needs a map to localize in (--load-map)");
  if (o.autosave_seconds < 0.0 || (o.autosave_seconds > 0.0 && !o.save_map))
    throw Error(
        fmt::format("run: --autosave {} needs a positive number of seconds and --save-map FILE "
                    "(where the map goes)",
                    o.autosave_seconds));
  if (o.localization_only && o.save_map)
    throw Error("run: --localization-only leaves the map as loaded: there is nothing new for --save-map");
  const std::shared_ptr<const io::FrameSource> source =
      o.source ? o.source : std::make_shared<const io::TumSequence>(io::TumSequence::open(o.sequence));
  const io::FrameSource& seq = *source;
  if (seq.size() == 0) throw file_error(seq.path(), "the sequence has no frames");
  // A rendered sequence's "path" names the preset and its options, not a file.
  report.source = seq.synthetic_benchmark() ? seq.path() : fs::absolute(seq.path()).lexically_normal();
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) throw file_error(o.out.string(), "cannot create the output folder: " + ec.message());
  if (o.save_masks) {
    fs::create_directories(*o.save_masks, ec);
    if (ec) throw file_error(o.save_masks->string(), "cannot create the mask folder: " + ec.message());
  }

  io::PrefetchOptions popts;
  if (o.max_frames > 0) popts.end = o.max_frames;
  if (o.preload) popts.queue_depth = std::max<std::size_t>(1, std::min(popts.end, seq.size()));
  const auto wall0 = std::chrono::steady_clock::now();
  io::FramePrefetcher frames(source, cfg.camera.depth_map_factor, popts);
  if (o.preload) frames.wait_until_decoded();
  SystemOptions sopts;
  sopts.deterministic = o.deterministic;
  sopts.localization_only = o.localization_only;
  sopts.yardstick = o.yardstick;
  // Declared before the system, so they outlive its threads (also on errors).
  std::shared_ptr<RepairRecorder> repairs;
  auto recorder = std::make_shared<RunRecorder>(seq, frames.size(), o.progress, o.save_masks);
  std::shared_ptr<FlagScorer> scorer;
  std::shared_ptr<SampleFrameRecorder> samples;
  System slam(cfg, params, sopts);
  // A bad map file stops the run here, before any frame is tracked.
  std::vector<Eigen::Vector3d> loaded_points;  // for the relocalization latency
  if (o.load_map) {
    slam.load_map(*o.load_map);
    for (const events::MapPointSnapshot& p : slam.map_snapshot().points) loaded_points.push_back(p.position);
  }
  report.loaded_map = o.load_map;
  report.localization_only = o.localization_only;
  if (slam.dense_enabled()) {
    repairs = std::make_shared<RepairRecorder>(seq, cfg.camera, o.save_repaired);
    slam.subscribe(repairs);
  }
  slam.subscribe(recorder);
  if (o.report_frames) {
    samples = std::make_shared<SampleFrameRecorder>();
    slam.subscribe(samples);
  }
  // Ground-truth masks (synthetic benchmark): the dynamic flags are scored on every n-th frame.
  const fs::path folder = data_folder(o);
  if (!folder.empty() && fs::is_directory(folder / "mask") && o.flag_eval_stride > 0) {
    scorer = std::make_shared<FlagScorer>(seq, folder / "mask", cfg.features, o.flag_eval_stride);
    slam.subscribe(scorer);
  }
  report.mode = dynamic::to_string(slam.mode());
  report.loop_closing = slam.loop_closing_enabled();
  report.vocabulary = slam.vocabulary_file().string();
  report.segmentation = slam.segmentation_description();

  std::shared_ptr<autosave::Autosaver> autosaver;
  if (o.autosave_seconds > 0.0) {
    autosaver = std::make_shared<autosave::Autosaver>(
        slam, autosave::AutosaveOptions{o.autosave_seconds, *o.save_map, o.out / "CameraTrajectory.txt"});
    slam.subscribe(autosaver);
    autosaver->start();
  }

  // Run.
  std::vector<std::size_t> during_saves;
  report.interrupted = !track_frames(slam, frames, o, seq, cfg.camera, report.camera_source, wall0,
                                     autosaver.get(), during_saves);
  if (autosaver) autosaver->stop();
  if (report.interrupted) spdlog::warn("interrupted: finishing the queued work and writing the outputs");
  slam.shutdown();
  // A signal while the queued work finished still counts (its handler promised the outputs).
  report.interrupted = report.interrupted || (o.interrupt != nullptr && o.interrupt->load());
  report.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const io::DecodeStats ds = frames.stats();
  report.decode_seconds = ds.decode_seconds;
  report.io_wait_seconds = ds.wait_seconds;
  report.log = recorder->take_log();
  if (o.save_map) {
    slam.save_map(*o.save_map);
    report.saved_map = o.save_map;
  }
  if (scorer) report.flags = scorer->score();
  if (autosaver)
    report.autosave = autosave_report(o.autosave_seconds, autosaver->stats(), report.log, during_saves);

  // Evaluate.
  evaluate(report, slam, o, seq, cfg, params, repairs, loaded_points);
  if (samples) {
    samples->write(o.out / "report_frames", slam.trajectory(), seq.ground_truth(),
                   scorer ? scorer->per_frame() : std::vector<FrameFlags>{});
    write_sparse_map_ply(o.out / "report_frames" / "sparse_map.ply", slam.map_snapshot());  // the 3-D view
  }
  return report;
}

}  // namespace lrd::runner
