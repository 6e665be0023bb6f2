#include "lrd/report/run_data.h"

#include <cmath>
#include <fstream>

#include "lrd/io/trajectory.h"
#include "lrd/report/html_page.h"
#include "lrd/report/map_view_data.h"
#include "lrd/report/track_times.h"
#include "lrd/report/trajectory_data.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::report {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

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

std::optional<fs::path> ground_truth_file(const RunSources& s, const json& summary) {
  // A run over a bag or a rendered sequence keeps its ground truth in the run folder.
  if (!s.sequence && fs::exists(s.run_dir / "groundtruth.txt")) return s.run_dir / "groundtruth.txt";
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
  const json frames = read_json_file(index);
  if (!frames.is_object() || !frames.contains("frames") || !frames.contains("repairs"))
    throw file_error(index, "not a list of sample frames (no \"frames\" and \"repairs\")");
  data["samples"] = inline_pictures(index, frames["frames"], "frames");
  data["repairs"] = inline_pictures(index, frames["repairs"], "repairs");
  if (frames.contains("yardstick") && frames["yardstick"].is_object())
    data["yardstick"] = frames["yardstick"];
  if (frames.contains("flags") && frames["flags"].is_object()) data["flags"] = frames["flags"];
}

}  // namespace

json read_json_file(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw file_error(file, "cannot read (not found?)");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw file_error(file, std::string("not valid JSON: ") + e.what());
  }
}

json collect_run_data(const RunSources& s) {
  json summary = read_json_file(s.run_dir / "summary.json");
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
  if (std::optional<json> map = map_view_data(s.run_dir)) data["map3d"] = std::move(*map);
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
