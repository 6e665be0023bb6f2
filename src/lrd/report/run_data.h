#pragma once
// What an HTML report shows about one run (docs/report.md), gathered from the run's output folder:
// summary.json, track_times.txt, CameraTrajectory.txt and the images the run wrote, with the
// sequence's ground truth when there is one. The page (web/report.js) draws it.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

namespace lrd::report {

struct RunSources {
  std::filesystem::path run_dir;  // a `lrdslam run --out` folder
  // Ground truth: SEQUENCE/groundtruth.txt; without it RUN_DIR/groundtruth.txt (a bag's or a
  // rendered sequence's run), else the folder summary.json names.
  std::optional<std::filesystem::path> sequence;
};

// Throws lrd::Error naming the file for a run folder without summary.json or track_times.txt, or
// with one that does not parse. Without ground truth the trajectory stays in its own frame.
[[nodiscard]] nlohmann::json collect_run_data(const RunSources& sources);

// A JSON file parsed; throws lrd::Error naming it when it cannot be read or is not JSON.
[[nodiscard]] nlohmann::json read_json_file(const std::filesystem::path& file);

}  // namespace lrd::report
