#pragma once
// Loop closing (ORB-SLAM2's LoopClosing thread, paper §2.2): each keyframe local mapping has
// processed is checked for a loop (LoopDetector); a detected loop is corrected:
//  1. the new keyframe and its covisible neighbours move rigidly to where the loop puts them,
//     with the map points they see;
//  2. the loop side's map points are fused with theirs (duplicates merged);
//  3. the essential graph (spanning tree, loop edges, strong covisibility edges and the new
//     loop connections) is optimized as a pose graph, and every map point follows its keyframe
//     (a dry run of it comes first: a loop whose correction would tear the spanning tree apart,
//     or that the graph cannot close, is refused before anything moves; loop_solution.h);
//  4. global bundle adjustment refines the whole map in its own thread and is merged without
//     stopping tracking (optim/global_bundle_adjuster.h).
// Tracking may suggest a loop (suggest_loop): relocalized where the camera cannot have gone since
// it was lost, it found the same place held twice by a map that drifted; verified, the loop
// merges the two copies, and the frames before the loss move with their keyframes.
// Trajectories follow automatically: frames are stored relative to keyframes.
//
// Threaded (default) it runs on its own thread; in lock-step mode (deterministic runs)
// process_queued() does the same work, global BA included, in the caller's thread.
#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "lrd/config/node_reader.h"
#include "lrd/loop/loop_closing_params.h"
#include "lrd/loop/loop_detector.h"
#include "lrd/map/reclamation.h"
#include "lrd/util/thread_errors.h"
#include "lrd/util/work_queue.h"

namespace lrd::map {
class KeyFrame;
class KeyFrameDatabase;
class Map;
}  // namespace lrd::map
namespace lrd::mapping {
class LocalMapper;
}

namespace lrd::loop {

// One closed loop, for the run log and the summary.
struct LoopEvent {
  std::uint64_t frame_id = 0;  // the frame that became the keyframe closing the loop
  double timestamp = 0.0;
  std::uint64_t keyframe_id = 0;
  std::uint64_t loop_keyframe_id = 0;
  int inliers = 0;            // matches supporting the loop after the projection search
  double correction_m = 0.0;  // how far the keyframe moved
  // Scale: the map's keyframes when the loop was corrected, the essential graph's
  // edges, and the latency of each step, so a benchmark can plot it against the map's size.
  std::size_t keyframes = 0;
  std::size_t pose_graph_edges = 0;
  double detection_seconds = 0.0;   // place recognition and the loop's relative pose
  double correction_seconds = 0.0;  // moving the neighbourhood, fusion, pose graph, every point
  // The solve with the fusion's links tore the odometry or left the loop open; the map took the
  // dry run's solution.
  bool dry_run_solution = false;
  bool suggested = false;  // suggested by tracking's relocalization (suggest_loop), not detected
};

// A loop suggested by tracking: relocalized into `loop_keyframe_id`'s part of the map where the
// camera cannot have gone since it was lost, the camera was last tracked against `keyframe_id`;
// `T_cw_guess` is that keyframe's pose in the loop's part, assuming the camera stood still
// meanwhile.
struct SuggestedLoop {
  std::uint64_t keyframe_id = 0;
  std::uint64_t loop_keyframe_id = 0;
  Eigen::Isometry3d T_cw_guess = Eigen::Isometry3d::Identity();
};

// One global bundle adjustment after a loop (its own thread when threaded).
struct GlobalBaRun {
  std::uint64_t loop_keyframe_id = 0;  // the keyframe whose loop started it
  int keyframes = 0, points = 0;       // solved
  double seconds = 0.0;                // from its start to merged (or dropped)
  bool aborted = false, implausible = false;
};

struct LoopCloserStats {
  std::vector<LoopEvent> loops;
  std::vector<GlobalBaRun> global_ba_runs;
  int rejected_loops = 0;  // detected, but contradicted by the map (loop_agreement.h) or implausible
  int global_bundle_adjustments = 0;
  int aborted_global_bundle_adjustments = 0;
  int implausible_global_bundle_adjustments = 0;  // solved but not merged
  double seconds = 0.0;                           // detection and correction (global BA not included)
  double global_ba_seconds = 0.0;
};

class LoopCloser {
 public:
  LoopCloser(map::Map& map, map::KeyFrameDatabase& database, mapping::LocalMapper& mapper,
             LoopClosingParams params, bool threaded);
  ~LoopCloser();
  LoopCloser(const LoopCloser&) = delete;
  LoopCloser& operator=(const LoopCloser&) = delete;

  // Where the threads' errors go (loop closing and global BA stop at the first); without a sink,
  // shutdown() rethrows it. Set before the first keyframe.
  void set_error_sink(util::ThreadErrors* errors) { errors_ = errors; }
  // Called in the loop-closing thread after each loop correction (map mutex not held).
  using LoopCallback = std::function<void(const LoopEvent&)>;
  void set_loop_callback(LoopCallback callback) { loop_callback_ = std::move(callback); }
  // From local mapping (any thread; the map mutex must not be held).
  void insert_keyframe(map::KeyFrame* kf);
  // From tracking (any thread, the map mutex may be held): verified and closed in turn with the
  // keyframes (LoopDetector::verify_suggested); stale once a loop was closed at its keyframe.
  void suggest_loop(const SuggestedLoop& loop);
  // Lock-step mode: processes what is queued now (and runs global BA to the end).
  void process_queued();
  // Processes what is queued, waits for a running global BA and stops the threads. Idempotent.
  void shutdown();
  [[nodiscard]] LoopCloserStats stats() const;

 private:
  // A keyframe local mapping processed, or a suggested loop.
  struct Work {
    std::uint64_t keyframe_id = 0;
    bool suggested = false;
    SuggestedLoop loop;  // when suggested
  };
  void run();
  void process(const Work& work);
  // Detects (or verifies the suggested) loop at `kf` (map mutex held).
  [[nodiscard]] std::optional<LoopDetection> find_loop(map::KeyFrame* kf, const Work& work);
  // Empty when the loop is rejected (agrees_with_map, correction_is_plausible); the map is then
  // untouched.
  std::optional<LoopEvent> correct_loop(const LoopDetection& loop);
  // A loop whose keyframe already shares structure with the current neighbourhood must agree
  // with it (loop_agreement.h); a warning names the loop otherwise.
  [[nodiscard]] bool agrees_with_map(const LoopDetection& loop,
                                     const std::vector<map::KeyFrame*>& neighbourhood,
                                     double correction_m) const;
  void run_global_ba(std::uint64_t run);
  void start_global_ba(std::uint64_t run);
  void stop_global_ba();

  map::Map& map_;
  map::KeyFrameDatabase& database_;
  mapping::LocalMapper& mapper_;
  const LoopClosingParams params_;
  const bool threaded_;
  LoopDetector detector_;  // this thread only

  util::ThreadErrors own_errors_;
  util::ThreadErrors* errors_ = &own_errors_;
  LoopCallback loop_callback_;
  util::WorkQueue<Work> queue_;  // by keyframe id: one may be removed while queued
  map::ReclamationMembership reclamation_;

  mutable std::mutex stats_mutex_;
  LoopCloserStats stats_;

  std::atomic<bool> abort_global_ba_{false};
  std::thread global_ba_thread_;
  std::thread thread_;
};

}  // namespace lrd::loop
