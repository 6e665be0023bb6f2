#include "lrd/report/run_data.h"

#include <cmath>
#include <fstream>

#include "lrd/eval/ate.h"
#include "lrd/io/trajectory.h"
#include "lrd/report/html_page.h"
#include "lrd/report/track_times.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::report {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Rounded so that the page stays small: 10 µm, 1 µs.
double round_to(double v, double step) {
  return std::round(v / step) * step;
}

json read_json(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw file_error(file, "cannot read (not found? give the folder a run wrote with --out)");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw file_error(file, std::string("not valid JSON: ") + e.what());
  }
}

json frame_columns(const std::vector<FrameTimes>& rows) {
  json stages = json::object();
  for (const std::string& name : stage_names()) stages[name] = json::array();
  json j = {{"index", json::array()},   {"t", json::array()},       {"state", json::array()},
            {"total", json::array()},   {"inliers", json::array()}, {"dynamic_keypoints", json::array()},
            {"mask_age", json::array()}};
  for (const FrameTimes& r : rows) {
    j["index"].push_back(r.index);
    j["t"].push_back(round_to(r.timestamp, 1e-6));
    j["state"].push_back(r.state);
    j["total"].push_back(round_to(r.total_ms, 1e-3));
    j["inliers"].push_back(r.inliers);
    j["dynamic_keypoints"].push_back(r.dynamic_keypoints);
    j["mask_age"].push_back(r.mask_age);
    for (std::size_t s = 0; s < stage_names().size(); ++s)
      stages[stage_names()[s]].push_back(round_to(r.stage_ms[s], 1e-3));
  }
  j["stages"] = stages;
  return j;
}

void push_position(json& xyz, const Eigen::Vector3d& p) {
  xyz["x"].push_back(round_to(p.x(), 1e-5));
  xyz["y"].push_back(round_to(p.y(), 1e-5));
  xyz["z"].push_back(round_to(p.z(), 1e-5));
}

json empty_xyz() {
  return {{"x", json::array()}, {"y", json::array()}, {"z", json::array()}};
}

// The estimate aligned onto the ground truth as the ATE aligns it (TUM's evaluate_ate.py), with
// each associated pose's error; the whole ground-truth path beside it.
json aligned_trajectory(const io::Trajectory& gt, const io::Trajectory& est) {
  const eval::AteResult ate = eval::compute_ate(gt, est);
  json j = {
      {"frame", "ground truth (world)"}, {"t", json::array()},    {"est", empty_xyz()}, {"gt", empty_xyz()},
      {"error", json::array()},          {"gt_path", empty_xyz()}};
  for (std::size_t i = 0; i < ate.matches.size(); ++i) {
    const io::StampedPose& e = est[ate.matches[i].second];
    j["t"].push_back(round_to(e.timestamp, 1e-6));
    push_position(j["est"], ate.alignment * e.pose.translation());
    push_position(j["gt"], gt[ate.matches[i].first].pose.translation());
    j["error"].push_back(round_to(ate.errors[i], 1e-5));
  }
  const std::size_t step = std::max<std::size_t>(1, gt.size() / 3000);  // a few thousand points at most
  for (std::size_t i = 0; i < gt.size(); i += step) push_position(j["gt_path"], gt[i].pose.translation());
  return j;
}

json own_frame_trajectory(const io::Trajectory& est) {
  json j = {
      {"frame", "the first camera's frame (no ground truth)"}, {"t", json::array()}, {"est", empty_xyz()}};
  for (const io::StampedPose& e : est) {
    j["t"].push_back(round_to(e.timestamp, 1e-6));
    push_position(j["est"], e.pose.translation());
  }
  return j;
}

std::optional<fs::path> ground_truth_file(const RunSources& s, const json& summary) {
  std::optional<fs::path> sequence = s.sequence;
  if (!sequence && summary.contains("sequence") && summary["sequence"].is_string())
    sequence = fs::path(summary["sequence"].get<std::string>());
  if (!sequence) return std::nullopt;
  if (s.sequence && !fs::is_directory(*sequence)) throw file_error(*sequence, "not a sequence folder");
  const fs::path gt = *sequence / "groundtruth.txt";
  if (fs::exists(gt)) return gt;
  return std::nullopt;
}

// The pictures a run writes beside its trajectory, when it wrote them.
json run_images(const fs::path& dir) {
  static const std::pair<const char*, const char*> kImages[] = {
      {"dense_map.png", "Dense map (rendered from the first keyframe's view)"},
      {"occupancy_2d.png", "Occupancy grid for navigation, with the camera path"},
  };
  json images = json::array();
  for (const auto& [name, title] : kImages)
    if (fs::exists(dir / name))
      images.push_back(
          {{"file", name},
           {"title", title},
           {"src", "data:image/png;base64," + base64(util::read_file_bytes(dir / name, "image"))}});
  return images;
}

// Inlines each listed picture of OUT/report_frames/ (a list named `key` in frames.json).
json inline_pictures(const fs::path& index, json list, const char* key) {
  if (!list.is_array()) throw file_error(index, std::string("\"") + key + "\" is not a list");
  for (json& f : list) {
    if (!f.is_object() || !f.contains("file") || !f["file"].is_string())
      throw file_error(index, std::string("an entry of \"") + key + "\" without a \"file\"");
    const fs::path image = index.parent_path() / f["file"].get<std::string>();
    f["src"] = "data:image/jpeg;base64," + base64(util::read_file_bytes(image, "sample picture"));
  }
  return list;
}

// The sample frames and background repairs `run --report` drew (runner/sample_frames.h).
void add_report_frames(json& data, const fs::path& dir) {
  const fs::path index = dir / "report_frames" / "frames.json";
  if (!fs::exists(index)) return;
  const json frames = read_json(index);
  if (!frames.is_object() || !frames.contains("frames") || !frames.contains("repairs"))
    throw file_error(index, "not a list of sample frames (no \"frames\" and \"repairs\")");
  data["samples"] = inline_pictures(index, frames["frames"], "frames");
  data["repairs"] = inline_pictures(index, frames["repairs"], "repairs");
  if (frames.contains("yardstick") && frames["yardstick"].is_object())
    data["yardstick"] = frames["yardstick"];
  if (frames.contains("flags") && frames["flags"].is_object()) data["flags"] = frames["flags"];
}

}  // namespace

json collect_run_data(const RunSources& s) {
  json summary = read_json(s.run_dir / "summary.json");
  if (!summary.is_object())
    throw file_error(s.run_dir / "summary.json", "not a run summary (not a JSON object)");
  json data = {{"run", fs::absolute(s.run_dir).lexically_normal().filename().string()},
               {"run_dir", fs::absolute(s.run_dir).lexically_normal().string()},
               {"summary", summary},
               {"frames", frame_columns(read_track_times(s.run_dir / "track_times.txt"))},
               {"images", run_images(s.run_dir)},
               {"samples", json::array()},
               {"repairs", json::array()}};
  add_report_frames(data, s.run_dir);
  const fs::path trajectory_file = s.run_dir / "CameraTrajectory.txt";
  const io::Trajectory est =
      fs::exists(trajectory_file) ? io::read_trajectory_tum(trajectory_file) : io::Trajectory{};
  const std::optional<fs::path> gt_file = ground_truth_file(s, summary);
  data["ground_truth"] = gt_file ? gt_file->string() : "";
  data["notes"] = json::array();
  if (gt_file && est.size() >= 2) {
    const io::Trajectory gt = io::read_trajectory_tum(*gt_file);  // a bad file stops the report
    try {
      data["trajectory"] = aligned_trajectory(gt, est);
      return data;
    } catch (const Error& e) {  // no pairs associate: shown in the estimate's own frame, with why
      data["notes"].push_back(std::string("no ATE against ") + gt_file->string() + ": " + e.what());
    }
  }
  data["trajectory"] = own_frame_trajectory(est);
  return data;
}

}  // namespace lrd::report
