#include "lrd/runner/sequence_runner.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <thread>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lrd/config/orbslam_settings.h"
#include "lrd/dense/cloud_renderer.h"
#include "lrd/dense/ply_io.h"
#include "lrd/dynamic/dynamic_params.h"
#include "lrd/eval/ate.h"
#include "lrd/eval/rpe.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/io/frame_prefetcher.h"
#include "lrd/io/trajectory.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/runner/dense_evaluation.h"
#include "lrd/runner/progress_bar.h"
#include "lrd/segmentation/onnx_presets.h"
#include "lrd/util/error.h"

namespace lrd::runner {

namespace fs = std::filesystem;

config::Config resolve_config(const RunOptions& o, std::string* source) {
  config::Config cfg = o.config ? config::load_config(*o.config) : config::Config{};
  std::string from;
  if (o.settings && o.preset) throw Error("--settings and --preset cannot be combined");
  if (o.settings) {
    const config::Settings s = config::read_orbslam_settings(*o.settings);
    cfg.camera = s.camera;
    cfg.features = s.orb;
    from = "settings " + o.settings->string();
  } else if (o.preset) {
    cfg.camera = camera::camera_preset(*o.preset);
    from = "preset " + *o.preset;
  } else if (cfg.camera_given) {
    from = "config " + cfg.file.string();
  } else if (fs::exists(o.sequence / "settings.yaml")) {
    const config::Settings s = config::read_orbslam_settings(o.sequence / "settings.yaml");
    cfg.camera = s.camera;
    from = "settings " + (o.sequence / "settings.yaml").string();
  } else {
    // TUM folder names carry the sensor: rgbd_dataset_freiburg3_walking_xyz.
    std::string name = fs::absolute(o.sequence).lexically_normal().filename().string();
    if (name.empty()) name = fs::absolute(o.sequence).lexically_normal().parent_path().filename().string();
    const std::size_t at = name.find("freiburg");
    const char sensor = at != std::string::npos && at + 8 < name.size() ? name[at + 8] : '\0';
    if (sensor >= '1' && sensor <= '3') {
      cfg.camera = camera::camera_preset(std::string("tum") + sensor);
      from = std::string("preset tum") + sensor + " (from the folder name)";
    } else {
      from = "preset tum3 (default)";
    }
  }
  if (source != nullptr) *source = from;
  return cfg;
}

segmentation::SegmentationParams segmenter_preset(const std::string& name, const fs::path& sequence,
                                                 segmentation::SegmentationParams p, const fs::path& model) {
  using segmentation::Backend;
  if (name == "none") {
    p.backend = Backend::None;
  } else if (name == "gt-masks" || name == "gt-masks-all") {
    p.backend = Backend::Masks;
    p.masks.folder = sequence / "mask";
    // Synthetic mask values: 1 person, 2 moved object (sequence.json "mask_values").
    p.masks.dynamic_values = name == "gt-masks" ? std::vector<int>{1} : std::vector<int>{1, 2};
  } else if (segmentation::is_onnx_preset(name)) {
    p.backend = Backend::Onnx;
    p.onnx = segmentation::onnx_preset(name, model);
  } else {
    throw Error("unknown segmenter '" + name +
                "' (choose none, gt-masks, gt-masks-all, fnet, selfie, selfie-landscape or espnetv2-voc)");
  }
  return p;
}

std::string default_segmenter(const fs::path& sequence) {
  // Our synthetic benchmark writes sequence.json; FNet-lite was trained on its renders. Real
  // camera data gets the network that knows real people.
  return fs::exists(sequence / "sequence.json") ? "fnet" : "selfie-landscape";
}

double FlagScore::precision() const {
  const std::size_t flagged = true_positive + false_positive;
  return flagged == 0 ? 0.0 : static_cast<double>(true_positive) / static_cast<double>(flagged);
}
double FlagScore::recall() const {
  const std::size_t dynamic = true_positive + false_negative;
  return dynamic == 0 ? 0.0 : static_cast<double>(true_positive) / static_cast<double>(dynamic);
}
double FlagScore::moved_object_recall() const {
  return moved_object == 0 ? 0.0 : static_cast<double>(moved_object_flagged) / static_cast<double>(moved_object);
}

namespace {

StageSummary summarize(std::vector<double> ms) {
  StageSummary s;
  if (ms.empty()) return s;
  s.mean_ms = std::accumulate(ms.begin(), ms.end(), 0.0) / static_cast<double>(ms.size());
  const std::size_t mid = ms.size() / 2;
  std::nth_element(ms.begin(), ms.begin() + static_cast<long>(mid), ms.end());
  s.median_ms = ms[mid];
  if (ms.size() % 2 == 0) {
    const double lower = *std::max_element(ms.begin(), ms.begin() + static_cast<long>(mid));
    s.median_ms = 0.5 * (s.median_ms + lower);
  }
  return s;
}

void write_track_times(const fs::path& file, const std::vector<FrameLog>& log) {
  std::ofstream out(file);
  // segmentation_ms runs in its own thread (not part of total_ms); mask_frame/mask_age say which
  // frame's mask was used (-1: none); dynamic_kps: keypoints the geometry check removed.
  out << "# frame timestamp extraction_ms segmentation_ms mask_wait_ms geometry_ms tracking_ms waiting_ms "
         "mapping_ms total_ms state inliers mask_frame mask_age dynamic_kps\n";
  for (const FrameLog& f : log)
    out << fmt::format("{} {:.6f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {} {} {} {} {}\n", f.index,
                       f.timestamp, 1e3 * f.timing.extraction, 1e3 * f.timing.segmentation, 1e3 * f.timing.mask_wait,
                       1e3 * f.timing.geometry, 1e3 * f.timing.tracking, 1e3 * f.timing.waiting,
                       1e3 * f.timing.mapping, 1e3 * f.timing.total(), tracking::to_string(f.state), f.inliers,
                       f.mask_frame, f.mask_age, f.geometric_keypoints);
  out.close();
  if (!out) throw file_error(file.string(), "cannot write");
}

nlohmann::json stage_json(const StageSummary& s) { return {{"median_ms", s.median_ms}, {"mean_ms", s.mean_ms}}; }

}  // namespace

void write_summary_json(const fs::path& file, const RunReport& r) {
  nlohmann::json j = {
      {"camera", r.camera_source},
      {"frames", r.frames},
      {"tracked", r.tracked},
      {"lost", r.lost},
      {"not_initialized", r.not_initialized},
      {"keyframes", r.map.keyframes},
      {"map_points", r.map.map_points},
      {"culled_keyframes", r.map.culled_keyframes},
      {"bundle_adjustments", r.map.bundle_adjustments},
      {"relocalizations", r.map.relocalizations},
      {"loop_closing", r.loop_closing},
      {"vocabulary", r.vocabulary},
      {"global_bundle_adjustments", r.map.global_bundle_adjustments},
      {"mode", r.mode},
      {"segmentation", r.segmentation},
      {"mean_mask_age", r.mean_mask_age},
      {"frames_without_mask", r.frames_without_mask},
      {"per_frame", {{"extraction", stage_json(r.extraction)},
                     {"segmentation", stage_json(r.segmentation_time)},
                     {"mask_wait", stage_json(r.mask_wait)},
                     {"geometry", stage_json(r.geometry)},
                     {"tracking", stage_json(r.tracking)},
                     {"waiting", stage_json(r.waiting)},
                     {"mapping", stage_json(r.mapping)},
                     {"total", stage_json(r.total)}}},
      {"wall_seconds", r.wall_seconds},
      {"decode_seconds", r.decode_seconds},
      {"io_wait_seconds", r.io_wait_seconds},
  };
  j["loops"] = nlohmann::json::array();
  for (const loop::LoopEvent& e : r.loops)
    j["loops"].push_back({{"frame", e.frame_id},
                          {"timestamp", e.timestamp},
                          {"keyframe", e.keyframe_id},
                          {"loop_keyframe", e.loop_keyframe_id},
                          {"inliers", e.inliers},
                          {"correction_m", e.correction_m}});
  if (r.has_ground_truth) {
    j["ate"] = {{"rmse", r.ate_rmse}, {"mean", r.ate_mean}, {"median", r.ate_median}, {"max", r.ate_max},
                {"pairs", r.ate_pairs}};
    j["rpe"] = {{"trans_rmse", r.rpe_trans_rmse}, {"rot_rmse", r.rpe_rot_rmse}};
  }
  if (r.flags) {
    j["dynamic_flags"] = {{"frames", r.flags->frames},
                          {"precision", r.flags->precision()},
                          {"recall", r.flags->recall()},
                          {"true_positive", r.flags->true_positive},
                          {"false_positive", r.flags->false_positive},
                          {"false_negative", r.flags->false_negative},
                          {"moved_object_keypoints", r.flags->moved_object},
                          {"moved_object_recall", r.flags->moved_object_recall()}};
  }
  if (r.dense) {
    const DenseReport& d = *r.dense;
    nlohmann::json repair = {{"keyframes", d.repair.keyframes},
                             {"dynamic_pixels", d.repair.dynamic_pixels},
                             {"filled_pixels", d.repair.filled_pixels},
                             {"fill_ratio", d.repair.fill_ratio()}};
    if (d.repair_median_depth_error) {
      repair["median_depth_error"] = *d.repair_median_depth_error;
      repair["compared_pixels"] = d.repair_compared_pixels;
    }
    j["dense"] = {{"points", d.points}, {"assemble_seconds", d.assemble_seconds}, {"repair", repair}};
    if (d.map)
      j["dense"]["map"] = {{"threshold", d.map->threshold},       {"map_points", d.map->map_points},
                           {"ghost_points", d.map->ghost_points}, {"ghost_ratio", d.map->ghost_ratio()},
                           {"median_distance", d.map->median_distance}, {"seen_samples", d.map->seen_samples},
                           {"covered_samples", d.map->covered_samples}, {"completeness", d.map->completeness()}};
  }
  std::ofstream out(file);
  out << j.dump(2) << '\n';
  out.close();
  if (!out) throw file_error(file.string(), "cannot write");
}

namespace {
// Writes the dense map and its picture, and judges repair and map where the sequence has truth.
DenseReport finish_dense(const System& slam, const RepairRecorder& repairs, const RunOptions& o,
                         const io::Trajectory& trajectory, const camera::PinholeCamera& camera, double max_depth) {
  DenseReport d;
  const auto t0 = std::chrono::steady_clock::now();
  const dense::PointCloud cloud = slam.dense_map();
  d.assemble_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  d.points = cloud.size();
  dense::write_ply(o.out / "dense_map.ply", cloud);
  const io::Trajectory keyframes = slam.keyframe_trajectory();
  if (!keyframes.empty() && cloud.size() > 0) {
    const cv::Mat picture =
        dense::render_cloud(cloud, camera, dense::overview_pose(cloud, keyframes.front().pose));
    const fs::path png = o.out / "dense_map.png";
    if (!cv::imwrite(png.string(), picture)) throw file_error(png, "cannot write");
  }
  d.repair = slam.repair_totals();
  if (repairs.has_truth()) {
    const RepairRecorder::DepthError e = repairs.depth_error();
    if (e.pixels > 0) {
      d.repair_median_depth_error = e.median;
      d.repair_compared_pixels = e.pixels;
    }
  }
  if (fs::exists(o.sequence / "scene.ply") && trajectory.size() >= 2) {
    try {
      d.map = evaluate_dense_map(cloud, trajectory, o.sequence, camera, max_depth);
    } catch (const std::exception& e) {
      spdlog::warn("dense map not judged: {}", e.what());
    }
  }
  return d;
}
}  // namespace

RunReport run_sequence(const RunOptions& o) {
  RunReport report;
  const config::Config cfg = resolve_config(o, &report.camera_source);
  const io::TumSequence seq = io::TumSequence::open(o.sequence);
  if (seq.size() == 0) throw file_error(o.sequence.string(), "the sequence has no frames");
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) throw file_error(o.out.string(), "cannot create the output folder: " + ec.message());

  io::PrefetchOptions popts;
  if (o.max_frames > 0) popts.end = o.max_frames;
  if (o.preload) popts.queue_depth = std::max<std::size_t>(1, std::min(popts.end, seq.size()));
  const auto wall0 = std::chrono::steady_clock::now();
  io::FramePrefetcher frames(seq, cfg.camera.depth_map_factor, popts);
  if (o.preload) frames.wait_until_decoded();
  SystemOptions sopts;
  sopts.deterministic = o.deterministic;
  if (o.mode) sopts.mode = dynamic::parse_mode(*o.mode);
  {
    auto seg = segmentation::SegmentationParams::from_config(cfg.segmentation,
                                                             cfg.file.empty() ? fs::path{} : cfg.file.parent_path());
    // A mode that needs masks with no segmenter configured gets the default network for the data.
    const dynamic::DynamicMode mode =
        o.mode ? dynamic::parse_mode(*o.mode) : dynamic::DynamicParams::from_config(cfg.dynamic).mode;
    std::optional<std::string> name = o.segmenter;
    if (!name && dynamic::uses_segmentation(mode) && seg.backend == segmentation::Backend::None)
      name = default_segmenter(o.sequence);
    if (name) sopts.segmentation = segmenter_preset(*name, o.sequence, seg, o.segmenter_model.value_or(fs::path{}));
  }
  if (o.dense || o.save_repaired) sopts.dense = true;
  if (o.no_loop_closing) sopts.loop_closing = false;
  if (o.vocabulary) sopts.vocabulary = *o.vocabulary;
  // Declared before the system, so it outlives the dense thread that calls it (also on errors).
  std::optional<RepairRecorder> repairs;
  System slam(cfg, sopts);
  if (slam.dense_enabled()) {
    repairs.emplace(seq, cfg.camera.depth_map_factor, o.save_repaired);
    slam.set_repair_callback([&repairs](double t, const dense::RgbdView& kf, const dense::RepairResult& r) {
      repairs->record(t, kf, r);
    });
  }
  report.mode = dynamic::to_string(slam.mode());
  report.loop_closing = slam.loop_closing_enabled();
  report.vocabulary = slam.vocabulary_file().string();
  report.segmentation = slam.segmentation_description();

  // Ground-truth masks (synthetic benchmark): score the dynamic flags on every n-th frame
  // against the keypoints an unmasked extractor finds there (outside the timed stages).
  const fs::path gt_masks = o.sequence / "mask";
  std::optional<features::OrbExtractor> reference_extractor;
  if (fs::is_directory(gt_masks) && o.flag_eval_stride > 0) {
    reference_extractor.emplace(cfg.features);
    report.flags.emplace();
  }
  if (o.save_masks) {
    fs::create_directories(*o.save_masks, ec);
    if (ec) throw file_error(o.save_masks->string(), "cannot create the mask folder: " + ec.message());
  }
  ProgressBar bar(frames.size(), o.progress);
  cv::Mat rgb, grey;
  std::vector<cv::KeyPoint> ref_kps;
  cv::Mat ref_desc;
  std::optional<double> first_stamp;
  while (auto f = frames.next()) {
    if (o.realtime) {
      // A live camera: frame k is not there before its timestamp's offset from the first frame.
      if (!first_stamp) first_stamp = f->timestamp;
      std::this_thread::sleep_until(wall0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                std::chrono::duration<double>(f->timestamp - *first_stamp)));
    }
    // The loader gives BGR; the system expects the camera's colour order.
    if (cfg.camera.rgb_order) cv::cvtColor(f->rgb, rgb, cv::COLOR_BGR2RGB);
    else rgb = f->rgb;
    const TrackResult r = slam.track_rgbd(rgb, f->depth, f->timestamp);
    report.log.push_back({f->index, f->timestamp, r.state, r.timing, r.inliers, r.dynamic.mask_frame,
                          r.dynamic.mask_age, r.dynamic.geometric_keypoints});
    if (o.save_masks) {
      const fs::path file = *o.save_masks / seq.entry(f->index).rgb_path.filename();
      const cv::Mat m = r.dynamic.mask.empty() ? cv::Mat::zeros(f->rgb.size(), CV_8UC1) : r.dynamic.mask;
      if (!cv::imwrite(file.string(), m)) throw file_error(file.string(), "cannot write the mask");
    }
    if (report.flags && f->index % static_cast<std::size_t>(o.flag_eval_stride) == 0) {
      const fs::path mask_file = gt_masks / seq.entry(f->index).rgb_path.filename();
      const cv::Mat truth = cv::imread(mask_file.string(), cv::IMREAD_UNCHANGED);
      if (!truth.empty() && truth.type() == CV_8UC1 && truth.size() == f->rgb.size()) {
        cv::cvtColor(f->rgb, grey, cv::COLOR_BGR2GRAY);
        reference_extractor->extract(grey, cv::Mat(), ref_kps, ref_desc);
        FlagScore& s = *report.flags;
        ++s.frames;
        for (const cv::KeyPoint& kp : ref_kps) {
          const int u = std::clamp(cvRound(kp.pt.x), 0, truth.cols - 1);
          const int v = std::clamp(cvRound(kp.pt.y), 0, truth.rows - 1);
          const std::uint8_t t = truth.at<std::uint8_t>(v, u);
          const bool flagged = !r.dynamic.mask.empty() && r.dynamic.mask.at<std::uint8_t>(v, u) != 0;
          if (t != 0) (flagged ? s.true_positive : s.false_negative)++;
          else (flagged ? s.false_positive : s.true_negative)++;
          if (t == 2) {
            ++s.moved_object;
            s.moved_object_flagged += flagged ? 1 : 0;
          }
        }
      }
    }
    bar.update(report.log.size(), fmt::format("{} ({} inliers)", tracking::to_string(r.state), r.inliers));
  }
  bar.finish();
  slam.shutdown();
  report.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const io::DecodeStats ds = frames.stats();
  report.decode_seconds = ds.decode_seconds;
  report.io_wait_seconds = ds.wait_seconds;

  report.frames = report.log.size();
  std::vector<double> ext, seg, mwait, geo, trk, wai, map, tot;
  double age_sum = 0.0;
  for (const FrameLog& f : report.log) {
    seg.push_back(1e3 * f.timing.segmentation);
    mwait.push_back(1e3 * f.timing.mask_wait);
    geo.push_back(1e3 * f.timing.geometry);
    if (f.mask_age >= 0) age_sum += f.mask_age;
    else ++report.frames_without_mask;
    report.tracked += f.state == TrackingState::Ok;
    report.lost += f.state == TrackingState::Lost;
    report.not_initialized += f.state == TrackingState::NotInitialized;
    ext.push_back(1e3 * f.timing.extraction);
    trk.push_back(1e3 * f.timing.tracking);
    wai.push_back(1e3 * f.timing.waiting);
    map.push_back(1e3 * f.timing.mapping);
    tot.push_back(1e3 * f.timing.total());
  }
  report.extraction = summarize(ext);
  report.segmentation_time = summarize(seg);
  report.mask_wait = summarize(mwait);
  report.geometry = summarize(geo);
  if (report.frames > report.frames_without_mask)
    report.mean_mask_age = age_sum / static_cast<double>(report.frames - report.frames_without_mask);
  report.tracking = summarize(trk);
  report.waiting = summarize(wai);
  report.mapping = summarize(map);
  report.total = summarize(tot);
  report.map = slam.map_stats();
  report.loops = slam.loops();

  const io::Trajectory trajectory = slam.trajectory();
  io::write_trajectory_tum(o.out / "CameraTrajectory.txt", trajectory);
  slam.save_keyframe_trajectory_tum(o.out / "KeyFrameTrajectory.txt");
  write_track_times(o.out / "track_times.txt", report.log);

  if (seq.groundtruth_path() && trajectory.size() >= 2) {
    const io::Trajectory gt = io::read_trajectory_tum(*seq.groundtruth_path());
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
    } catch (const Error& e) {
      spdlog::warn("no ATE/RPE: {} vs {}: {}", (o.out / "CameraTrajectory.txt").string(),
                   seq.groundtruth_path()->string(), e.what());
    }
  }
  if (slam.dense_enabled()) report.dense = finish_dense(slam, *repairs, o, trajectory, cfg.camera,
                                                         dense::DenseParams::from_config(cfg.dense).max_depth);
  write_summary_json(o.out / "summary.json", report);
  return report;
}

}  // namespace lrd::runner
