#pragma once
// Runs lrd::System over a TUM-layout sequence folder (real TUM RGB-D or our synthetic benchmark):
// decodes frames ahead on their own thread, tracks them, writes the trajectories and per-frame
// timings, and evaluates against the ground truth when the folder has one. `lrdslam run` and the
// benchmarks both use it.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "lrd/config/config.h"
#include "lrd/system.h"

namespace lrd::runner {

struct RunOptions {
  std::filesystem::path sequence;               // folder with rgb.txt / depth.txt or associations.txt
  std::optional<std::filesystem::path> settings;  // ORB-SLAM2/3 settings file
  std::optional<std::string> preset;            // camera preset (tum1, tum2, tum3)
  std::optional<std::filesystem::path> config;  // lrd-slam YAML config
  std::filesystem::path out;                    // output folder (created)
  bool deterministic = false;
  std::size_t max_frames = 0;  // 0: all
  bool progress = true;        // progress bar on stderr
};

// Chooses the camera: --settings, else --preset, else the config's camera section if the config
// has one, else the sequence's own settings.yaml (synthetic benchmark), else the TUM preset named
// by a "freiburgN" folder name, else the default (tum3). `source` says which was used.
[[nodiscard]] config::Config resolve_config(const RunOptions& options, std::string* source = nullptr);

struct FrameLog {
  std::size_t index = 0;
  double timestamp = 0.0;
  TrackingState state = TrackingState::NotInitialized;
  FrameTiming timing;
  int inliers = 0;
};

struct StageSummary {
  double median_ms = 0.0;
  double mean_ms = 0.0;
};

struct RunReport {
  std::string camera_source;
  std::size_t frames = 0;
  std::size_t tracked = 0;
  std::size_t lost = 0;
  std::size_t not_initialized = 0;
  MapStats map;
  StageSummary extraction, tracking, waiting, mapping, total;  // per frame, without decoding
  double wall_seconds = 0.0;    // whole run including decoding
  double decode_seconds = 0.0;  // decoder thread's busy time
  double io_wait_seconds = 0.0; // tracking thread waiting on decoded frames
  std::vector<FrameLog> log;
  bool has_ground_truth = false;
  double ate_rmse = 0.0, ate_mean = 0.0, ate_median = 0.0, ate_max = 0.0;  // metres
  double rpe_trans_rmse = 0.0;  // m/s
  double rpe_rot_rmse = 0.0;    // deg/s
  std::size_t ate_pairs = 0;
};

[[nodiscard]] RunReport run_sequence(const RunOptions& options);

// Writes summary.json next to the trajectories (called by run_sequence).
void write_summary_json(const std::filesystem::path& file, const RunReport& report);

}  // namespace lrd::runner
