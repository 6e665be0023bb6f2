#pragma once
// Runs lrd::System over a TUM-layout sequence folder (real TUM RGB-D or our synthetic benchmark):
// decodes frames ahead on their own thread, tracks them, writes the trajectories and per-frame
// timings, and evaluates against the ground truth when the folder has one. `lrdslam run` and the
// benchmarks both use it.
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lrd/config/config.h"
#include "lrd/eval/map_accuracy.h"
#include "lrd/eval/occupancy_accuracy.h"
#include "lrd/eval/statistics.h"
#include "lrd/io/frame_source.h"
#include "lrd/runner/localization_latency.h"
#include "lrd/system.h"

namespace lrd::runner {

struct RunOptions {
  std::filesystem::path sequence;  // folder with rgb.txt / depth.txt or associations.txt
  // Frames from another source instead of the folder (a rosbag: lrd_ros::BagSequence, in a build
  // with ROS). Its camera, if it carries one, comes after --settings, --preset and the config's.
  std::shared_ptr<const io::FrameSource> source;
  std::optional<std::filesystem::path> settings;  // ORB-SLAM2/3 settings file
  std::optional<std::string> preset;              // camera preset (tum1, tum2, tum3, bonn)
  std::optional<std::filesystem::path> config;    // lrd-slam YAML config
  std::filesystem::path out;                      // output folder (created; empty: the config's output.dir)
  bool deterministic = false;
  std::optional<std::string> mode;       // static | semantic | geometric | full (else the config's)
  std::optional<std::string> segmenter;  // a segmenter preset (see segmenter_preset), else the config's
  std::optional<std::filesystem::path> segmenter_model;  // the preset's model file (espnetv2-voc needs it)
  std::size_t max_frames = 0;                            // 0: all
  // Writes each frame's final dynamic mask (255 = dynamic) here, named like its colour image, so
  // the folder can be inspected or fed back as a `masks` backend cache.
  std::optional<std::filesystem::path> save_masks;
  // Dense map (background repair + point cloud): writes dense_map.ply and dense_map.png, and judges
  // the map against scene.ply when the sequence has one.
  bool dense = false;
  // true: the occupancy map and 2-D grid (occupancy.bt, occupancy_2d.*), implying the dense stage;
  // false: not even with it; unset: the config's occupancy.enabled with the dense stage.
  std::optional<bool> occupancy;
  // Writes each repaired keyframe (colour, depth, mask; originals beside them) here; implies the
  // dense stage's repair.
  std::optional<std::filesystem::path> save_repaired;
  // OUT/report_frames/: sample frames drawn for the HTML report (runner/sample_frames.h).
  bool report_frames = false;
  // Feed frames no faster than their timestamps (a live camera) instead of as fast as they are
  // tracked: the cores then have the idle time a real camera leaves the background threads.
  bool realtime = false;
  // Decode every frame before the first is tracked (memory: ~2 MB a frame) instead of beside
  // tracking: per-frame times then carry no decoding thread competing for the cores, as in
  // ORB-SLAM2's measurement (it decodes between frames). The benchmarks use it.
  bool preload = false;
  // --no-loop-closing (ablations; relocalization stays), --vocabulary FILE.
  bool no_loop_closing = false;
  std::optional<std::filesystem::path> vocabulary;
  // Map files (docs/map-files.md): start from a saved map (frames relocalize against it first),
  // track it without adding to it, write the final map.
  std::optional<std::filesystem::path> load_map;
  bool localization_only = false;  // needs load_map
  std::optional<std::filesystem::path> save_map;
  // > 0 (needs save_map): the map to save_map and the trajectory so far to OUT/CameraTrajectory.txt
  // every so many seconds and after each loop closure, on a thread of their own
  // (autosave/autosaver.h): a run killed hard leaves its last complete save.
  double autosave_seconds = 0.0;
  int flag_eval_stride = 5;  // with ground-truth masks: judge the dynamic flags on every n-th frame
  bool progress = true;      // progress bar on stderr
  // Benchmarks: Y measured in the tracking thread beside each frame's extraction
  // (SystemOptions::yardstick); RunReport::yardstick.
  bool yardstick = false;
  // Set (e.g. by a SIGINT handler) to stop reading frames: the run finishes the queued work and
  // writes every output from the frames done, with `interrupted` in the report.
  const std::atomic<bool>* interrupt = nullptr;
};

// Chooses the camera: --settings, else --preset, else the config's camera section if the config
// has one, else the camera the frame source carries (a bag's camera_info), else the sequence's own
// settings.yaml (synthetic benchmark), else the TUM preset named by a "freiburgN" folder (or bag)
// name, else the bonn preset for an "rgbd_bonn_*" folder, else the default (tum3). `source` says which was
// used.
[[nodiscard]] config::Config resolve_config(const RunOptions& options, std::string* source = nullptr);
// The same over a config already read (options.config is then not read).
[[nodiscard]] config::Config resolve_config(const RunOptions& options, config::Config config,
                                            std::string* source = nullptr);

// A carried camera (a bag's or a topic's camera_info) over `base`: the sensor's intrinsics,
// distortion and size; base's depth settings stay (a camera_info has none).
[[nodiscard]] camera::PinholeCamera camera_from_source(const io::SourceCamera& source,
                                                       camera::PinholeCamera base);

// Segmentation presets for --segmenter (the config's `segmentation` section supplies the
// schedule and dilation):
//   none          no segmentation
//   gt-masks      the synthetic benchmark's ground truth, people only (what a semantic network
//                 can know: a pushed chair is still a chair) — the upper bound for the network
//   gt-masks-all  ground truth of everything that moves (people, moved objects, balloons)
//   fnet, selfie, selfie-landscape, espnetv2-voc
//                 the onnx presets (segmentation/onnx_presets.h); `model` overrides their file
// Throws lrd::Error for an unknown name.
[[nodiscard]] segmentation::SegmentationParams segmenter_preset(const std::string& name,
                                                                const std::filesystem::path& sequence,
                                                                segmentation::SegmentationParams base,
                                                                const std::filesystem::path& model = {});

// The segmenter a semantic/full run gets when none is configured: fnet for our synthetic
// benchmark (it has sequence.json), selfie-landscape for real data (and for a source without a
// folder, an empty path).
[[nodiscard]] std::string default_segmenter(const std::filesystem::path& sequence);

// The folder of a run's extra files: the sequence folder, or the source's (empty for a bag).
[[nodiscard]] std::filesystem::path data_folder(const RunOptions& options);

struct FrameLog {
  std::size_t index = 0;
  double timestamp = 0.0;
  TrackingState state = TrackingState::NotInitialized;
  FrameTiming timing;
  int inliers = 0;
  std::int64_t mask_frame = -1;
  int mask_age = -1;
  int geometric_keypoints = 0;
};

// Dynamic keypoint flags against ground-truth masks: over the keypoints an unmasked extractor
// finds, "flagged" = inside the frame's final dynamic mask, "dynamic" = on a moving object.
struct FlagScore {
  std::size_t frames = 0;
  std::size_t true_positive = 0, false_positive = 0, false_negative = 0, true_negative = 0;
  // Per class of what moves (the mask's values): keypoints on it, and how many were flagged.
  std::size_t person = 0, person_flagged = 0;
  std::size_t moved_object = 0, moved_object_flagged = 0;  // pushed chairs, carried boxes
  std::size_t balloon = 0, balloon_flagged = 0;
  [[nodiscard]] double precision() const;
  [[nodiscard]] double recall() const;
  [[nodiscard]] double person_recall() const;
  [[nodiscard]] double moved_object_recall() const;
  [[nodiscard]] double balloon_recall() const;
};

// One scored frame's dynamic flags (FlagScorer), for the report's precision and recall over time.
struct FrameFlags {
  std::size_t frame = 0;
  std::size_t true_positive = 0, false_positive = 0, false_negative = 0;
};

struct StageSummary {
  double median_ms = 0.0;
  double mean_ms = 0.0;
};

struct DenseReport {
  std::size_t points = 0;         // in dense_map.ply
  double assemble_seconds = 0.0;  // merging the keyframes' clouds at their final poses
  dense::RepairTotals repair;
  dense::DenseStorage storage;                      // the keyframes' stored clouds at the end
  std::optional<double> repair_median_depth_error;  // m, vs static/depth (synthetic benchmark)
  std::size_t repair_compared_pixels = 0;
  std::optional<eval::MapAccuracy> map;  // vs scene.ply (synthetic benchmark)
};

// The occupancy outputs (occupancy.bt, occupancy_2d.*; docs/occupancy.md).
struct OccupancyReport {
  double resolution = 0.0;
  std::size_t occupied_voxels = 0, free_voxels = 0;
  Eigen::Vector3d up = Eigen::Vector3d::Zero();  // map frame
  double floor_height = 0.0;                     // along up from the map origin
  int grid_width = 0, grid_height = 0;
  std::size_t grid_occupied = 0, grid_free = 0, grid_unknown = 0;
  double build_seconds = 0.0;                       // ray casting every keyframe at its final pose
  std::optional<eval::OccupancyAccuracy> accuracy;  // vs scene.ply (synthetic benchmark)
};

// The autosaves of a run (RunOptions::autosave_seconds), and what they cost tracking: the frames
// tracked while a save was under way against the others.
struct AutosaveReport {
  double period_seconds = 0.0;
  std::size_t saves = 0, loop_saves = 0, failures = 0;
  double save_median_ms = 0.0, save_max_ms = 0.0;  // capture, bytes, both files written and synced
  double lock_median_ms = 0.0, lock_max_ms = 0.0;  // the map mutex held per save
  std::size_t frames_during_saves = 0;
  std::vector<std::size_t> frame_indices_during_saves;  // to compare with the same frames of another run
  double total_median_ms_during_saves = 0.0;            // FrameTiming::total() of those frames
  double total_median_ms_otherwise = 0.0;               // and of the other frames
};

struct RunReport {
  std::filesystem::path out;  // the output folder written
  bool interrupted = false;   // stopped early by RunOptions::interrupt
  std::string camera_source;
  std::filesystem::path source;  // the sequence folder or bag read
  std::size_t frames = 0;
  std::size_t tracked = 0;
  std::size_t lost = 0;
  std::size_t not_initialized = 0;
  std::size_t not_localized = 0;  // frames before the first placed in a loaded map
  MapStats map;
  std::optional<std::filesystem::path> loaded_map, saved_map;  // RunOptions::load_map / save_map
  bool localization_only = false;
  LocalizationLatency localization;      // with a loaded map (first view: with ground truth)
  double not_localized_median_ms = 0.0;  // per frame, while relocalizing in the loaded map
  std::vector<loop::LoopEvent> loops;
  bool loop_closing = false;
  std::string vocabulary;    // file in use ("" : none)
  std::string mode;          // static | semantic | geometric | full
  std::string segmentation;  // backend and schedule
  StageSummary extraction, segmentation_time, mask_wait, geometry, tracking, waiting, mapping,
      total;                   // per frame, without decoding
  StageSummary yardstick;      // RunOptions::yardstick: OpenCV ORB per frame (median: the interleaved Y)
  double mean_mask_age = 0.0;  // frames, over frames with a mask
  std::size_t frames_without_mask = 0;
  std::optional<FlagScore> flags;  // when the sequence has ground-truth masks
  double wall_seconds = 0.0;       // whole run including decoding
  double decode_seconds = 0.0;     // decoder thread's busy time
  double io_wait_seconds = 0.0;    // tracking thread waiting on decoded frames
  std::vector<FrameLog> log;
  bool has_ground_truth = false;
  double ate_rmse = 0.0, ate_mean = 0.0, ate_median = 0.0, ate_max = 0.0;  // metres
  double rpe_trans_rmse = 0.0;                                             // m/s
  double rpe_rot_rmse = 0.0;                                               // deg/s
  std::size_t ate_pairs = 0;
  eval::ErrorStats ate, rpe_trans, rpe_rot;  // full statistics (m; m/s and deg/s at delta 1 s)
  std::optional<DenseReport> dense;
  std::optional<OccupancyReport> occupancy;
  std::optional<AutosaveReport> autosave;
};

// Runs a sequence in three steps: configure (camera, config, SystemParams with the segmenter
// chosen), run (frames through lrd::System; subscribers record the log, the progress, masks and
// the dynamic-flag scores), evaluate (trajectories, ATE/RPE, dense map, summary.json).
[[nodiscard]] RunReport run_sequence(const RunOptions& options);

// The parameters of a run: the config's, with the command line's mode, segmenter, dense and
// loop-closing choices (a mode that needs masks gets default_segmenter when none is configured).
[[nodiscard]] SystemParams configure_system(const RunOptions& options, const config::Config& config);

// Per-stage statistics and frame counts of report.log.
void summarize_log(RunReport& report);
void write_track_times(const std::filesystem::path& file, const std::vector<FrameLog>& log);

// Writes summary.json next to the trajectories (called by run_sequence).
void write_summary_json(const std::filesystem::path& file, const RunReport& report);

}  // namespace lrd::runner
