// Evaluate's outputs: per-stage statistics, track_times.txt and summary.json.
#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <numeric>

#include "lrd/runner/sequence_runner.h"
#include "lrd/util/atomic_file.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::runner {

namespace fs = std::filesystem;

double FlagScore::precision() const {
  const std::size_t flagged = true_positive + false_positive;
  return flagged == 0 ? 0.0 : static_cast<double>(true_positive) / static_cast<double>(flagged);
}
double FlagScore::recall() const {
  const std::size_t dynamic = true_positive + false_negative;
  return dynamic == 0 ? 0.0 : static_cast<double>(true_positive) / static_cast<double>(dynamic);
}
namespace {
double share(std::size_t part, std::size_t whole) {
  return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}
}  // namespace
double FlagScore::person_recall() const {
  return share(person_flagged, person);
}
double FlagScore::moved_object_recall() const {
  return share(moved_object_flagged, moved_object);
}
double FlagScore::balloon_recall() const {
  return share(balloon_flagged, balloon);
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

}  // namespace

void write_track_times(const fs::path& file, const std::vector<FrameLog>& log) {
  util::AtomicFile file_out(file);
  std::ostream& out = file_out.stream();
  // segmentation_ms runs in its own thread (not part of total_ms); mask_frame/mask_age say which
  // frame's mask was used (-1: none); dynamic_kps: keypoints the geometry check removed.
  out << "# frame timestamp extraction_ms segmentation_ms mask_wait_ms geometry_ms tracking_ms waiting_ms "
         "mapping_ms total_ms state inliers mask_frame mask_age dynamic_kps\n";
  for (const FrameLog& f : log)
    out << fmt::format("{} {:.6f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {} {} {} {} {}\n",
                       f.index, f.timestamp, 1e3 * f.timing.extraction, 1e3 * f.timing.segmentation,
                       1e3 * f.timing.mask_wait, 1e3 * f.timing.geometry, 1e3 * f.timing.tracking,
                       1e3 * f.timing.waiting, 1e3 * f.timing.mapping, 1e3 * f.timing.total(),
                       tracking::to_string(f.state), f.inliers, f.mask_frame, f.mask_age,
                       f.geometric_keypoints);
  file_out.commit();
}

void summarize_log(RunReport& report) {
  report.frames = report.log.size();
  std::vector<double> ext, seg, mwait, geo, trk, wai, map, tot, relocalizing, yardstick;
  double age_sum = 0.0;
  for (const FrameLog& f : report.log) {
    seg.push_back(1e3 * f.timing.segmentation);
    mwait.push_back(1e3 * f.timing.mask_wait);
    geo.push_back(1e3 * f.timing.geometry);
    if (f.mask_age >= 0)
      age_sum += f.mask_age;
    else
      ++report.frames_without_mask;
    report.tracked += f.state == TrackingState::Ok;
    report.lost += f.state == TrackingState::Lost;
    report.not_initialized += f.state == TrackingState::NotInitialized;
    report.not_localized += f.state == TrackingState::NotLocalized;
    if (f.state == TrackingState::NotLocalized) relocalizing.push_back(1e3 * f.timing.total());
    ext.push_back(1e3 * f.timing.extraction);
    trk.push_back(1e3 * f.timing.tracking);
    wai.push_back(1e3 * f.timing.waiting);
    map.push_back(1e3 * f.timing.mapping);
    tot.push_back(1e3 * f.timing.total());
    if (f.timing.yardstick > 0.0) yardstick.push_back(1e3 * f.timing.yardstick);
  }
  report.yardstick = summarize(yardstick);
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
  report.not_localized_median_ms = summarize(relocalizing).median_ms;
}

namespace {
nlohmann::json stage_json(const StageSummary& s) {
  return {{"median_ms", s.median_ms}, {"mean_ms", s.mean_ms}};
}

nlohmann::json error_stats_json(const eval::ErrorStats& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std_dev},
          {"min", s.min},   {"max", s.max},   {"pairs", s.count}};
}

}  // namespace

void write_summary_json(const fs::path& file, const RunReport& r) {
  nlohmann::json j = {
      {"sequence", r.source.string()},
      {"camera", r.camera_source},
      {"frames", r.frames},
      {"tracked", r.tracked},
      {"lost", r.lost},
      {"not_initialized", r.not_initialized},
      {"not_localized", r.not_localized},
      {"keyframes", r.map.keyframes},
      {"map_points", r.map.map_points},
      {"culled_keyframes", r.map.culled_keyframes},
      {"bundle_adjustments", r.map.bundle_adjustments},
      {"implausible_local_bundle_adjustments", r.map.implausible_local_bundle_adjustments},
      {"relocalizations", r.map.relocalizations},
      {"implausible_camera_motions", r.map.implausible_camera_motions},
      {"loop_closing", r.loop_closing},
      {"vocabulary", r.vocabulary},
      {"global_bundle_adjustments", r.map.global_bundle_adjustments},
      {"implausible_global_bundle_adjustments", r.map.implausible_global_bundle_adjustments},
      {"rejected_loops", r.map.rejected_loops},
      {"mode", r.mode},
      {"segmentation", r.segmentation},
      {"mean_mask_age", r.mean_mask_age},
      {"frames_without_mask", r.frames_without_mask},
      {"per_frame",
       {{"extraction", stage_json(r.extraction)},
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
      {"interrupted", r.interrupted},
  };
  // Y measured in the run's tracking thread beside each frame (`run --yardstick`).
  if (r.yardstick.median_ms > 0.0) j["per_frame"]["yardstick"] = stage_json(r.yardstick);
  if (r.loaded_map || r.saved_map)
    j["map_file"] = {{"loaded", r.loaded_map ? r.loaded_map->string() : ""},
                     {"loaded_keyframes", r.map.loaded_keyframes},
                     {"loaded_map_points", r.map.loaded_map_points},
                     {"localization_only", r.localization_only},
                     {"saved", r.saved_map ? r.saved_map->string() : ""},
                     {"not_localized_median_ms", r.not_localized_median_ms}};
  if (r.loaded_map) {
    const auto optional_index = [](const std::optional<std::size_t>& v) {
      return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
    };
    j["map_file"]["first_localized_frame"] = optional_index(r.localization.first_localized_frame);
    j["map_file"]["first_view_frame"] = optional_index(r.localization.first_view_frame);
    j["map_file"]["relocalization_frames"] = optional_index(r.localization.frames());
  }
  if (r.autosave) {
    const AutosaveReport& a = *r.autosave;
    j["autosave"] = {{"period_seconds", a.period_seconds},
                     {"saves", a.saves},
                     {"loop_saves", a.loop_saves},
                     {"failures", a.failures},
                     {"save_median_ms", a.save_median_ms},
                     {"save_max_ms", a.save_max_ms},
                     {"lock_median_ms", a.lock_median_ms},
                     {"lock_max_ms", a.lock_max_ms},
                     {"frames_during_saves", a.frames_during_saves},
                     {"frame_indices_during_saves", a.frame_indices_during_saves},
                     {"total_median_ms_during_saves", a.total_median_ms_during_saves},
                     {"total_median_ms_otherwise", a.total_median_ms_otherwise}};
  }
  j["loops"] = nlohmann::json::array();
  for (const loop::LoopEvent& e : r.loops)
    j["loops"].push_back({{"frame", e.frame_id},
                          {"timestamp", e.timestamp},
                          {"keyframe", e.keyframe_id},
                          {"loop_keyframe", e.loop_keyframe_id},
                          {"inliers", e.inliers},
                          {"correction_m", e.correction_m},
                          {"map_keyframes", e.keyframes},
                          {"pose_graph_edges", e.pose_graph_edges},
                          {"detection_ms", 1e3 * e.detection_seconds},
                          {"correction_ms", 1e3 * e.correction_seconds},
                          {"dry_run_solution", e.dry_run_solution},
                          {"suggested", e.suggested}});
  if (r.has_ground_truth) {
    j["ate"] = {{"rmse", r.ate_rmse},   {"mean", r.ate_mean}, {"median", r.ate_median},
                {"std", r.ate.std_dev}, {"max", r.ate_max},   {"pairs", r.ate_pairs}};
    // The paper's Tables 6-7 need every statistic of both RPE parts (m/s, deg/s at delta 1 s).
    j["rpe"] = {{"trans_rmse", r.rpe_trans_rmse},
                {"rot_rmse", r.rpe_rot_rmse},
                {"trans", error_stats_json(r.rpe_trans)},
                {"rot", error_stats_json(r.rpe_rot)}};
  }
  if (r.flags) {
    j["dynamic_flags"] = {{"frames", r.flags->frames},
                          {"precision", r.flags->precision()},
                          {"recall", r.flags->recall()},
                          {"true_positive", r.flags->true_positive},
                          {"false_positive", r.flags->false_positive},
                          {"false_negative", r.flags->false_negative},
                          {"person_keypoints", r.flags->person},
                          {"person_recall", r.flags->person_recall()},
                          {"moved_object_keypoints", r.flags->moved_object},
                          {"moved_object_recall", r.flags->moved_object_recall()},
                          {"balloon_keypoints", r.flags->balloon},
                          {"balloon_recall", r.flags->balloon_recall()}};
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
    const nlohmann::json storage = {{"keyframes", d.storage.keyframes},
                                    {"points", d.storage.points},
                                    {"mib", static_cast<double>(d.storage.bytes) / (1024.0 * 1024.0)},
                                    {"max_memory_mb", d.storage.max_memory_mb},
                                    {"evicted_keyframes", d.storage.evicted_keyframes},
                                    {"evicted_active_keyframes", d.storage.evicted_active}};
    j["dense"] = {{"points", d.points},
                  {"assemble_seconds", d.assemble_seconds},
                  {"repair", repair},
                  {"storage", storage}};
    if (d.map)
      j["dense"]["map"] = {{"threshold", d.map->threshold},
                           {"map_points", d.map->map_points},
                           {"ghost_points", d.map->ghost_points},
                           {"ghost_ratio", d.map->ghost_ratio()},
                           {"median_distance", d.map->median_distance},
                           {"seen_samples", d.map->seen_samples},
                           {"covered_samples", d.map->covered_samples},
                           {"completeness", d.map->completeness()}};
  }
  if (r.occupancy) {
    const OccupancyReport& o = *r.occupancy;
    j["occupancy"] = {{"resolution", o.resolution},      {"occupied_voxels", o.occupied_voxels},
                      {"free_voxels", o.free_voxels},    {"up", {o.up.x(), o.up.y(), o.up.z()}},
                      {"floor_height", o.floor_height},  {"grid_width", o.grid_width},
                      {"grid_height", o.grid_height},    {"grid_occupied_cells", o.grid_occupied},
                      {"grid_free_cells", o.grid_free},  {"grid_unknown_cells", o.grid_unknown},
                      {"build_seconds", o.build_seconds}};
    if (o.accuracy) {
      const eval::OccupancyAccuracy& a = *o.accuracy;
      j["occupancy"]["scene"] = {{"precision", a.precision()},
                                 {"recall", a.recall()},
                                 {"occupied_voxels", a.occupied_voxels},
                                 {"seen_scene_voxels", a.seen_scene_voxels},
                                 {"people_voxels", a.people_voxels},
                                 {"people_ghosts", a.people_ghosts},
                                 {"people_ghost_share", a.people_ghost_share()},
                                 {"grid_precision", a.grid_precision()},
                                 {"grid_recall", a.grid_recall()},
                                 {"path_cells", a.path_cells},
                                 {"path_blocked_cells", a.path_blocked_cells},
                                 {"path_free_cells", a.path_free_cells},
                                 {"path_blocked_share", a.path_blocked_share()}};
    }
  }
  util::write_file_bytes(file, j.dump(2) + '\n');
}

}  // namespace lrd::runner
