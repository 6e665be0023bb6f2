#pragma once
// Local mapping (ORB-SLAM2's LocalMapping, paper §2.2): takes the keyframes tracking decides on
// and grows the map around them: registers their observations, culls recent map points that
// tracking fails to find, triangulates new points with covisible keyframes, fuses duplicates,
// runs local bundle adjustment and removes redundant keyframes.
//
// Threaded (default) it runs on its own thread, fed by a queue; in lock-step mode (deterministic
// runs) process_queued() does the same work in the caller's thread after each keyframe, so that
// the result does not depend on thread timing.
#include <atomic>
#include <cstdint>
#include <functional>
#include <list>
#include <mutex>
#include <thread>

#include "lrd/config/node_reader.h"
#include "lrd/map/reclamation.h"
#include "lrd/mapping/keyframe_culling.h"
#include "lrd/mapping/local_mapper_params.h"
#include "lrd/match/orb_matcher.h"
#include "lrd/optim/local_bundle_adjuster.h"
#include "lrd/util/thread_errors.h"
#include "lrd/util/work_queue.h"

namespace lrd::map {
class KeyFrame;
class KeyFrameDatabase;
class Map;
class MapPoint;
}  // namespace lrd::map

namespace lrd::place {
class Vocabulary;
}
namespace lrd::mapping {

struct LocalMapperStats {
  std::uint64_t keyframes = 0;
  std::uint64_t culled_keyframes = 0;
  std::uint64_t triangulated_points = 0;
  std::uint64_t bundle_adjustments = 0;
  std::uint64_t aborted_bundle_adjustments = 0;
  std::uint64_t implausible_bundle_adjustments = 0;  // solved, refused (optim/local_bundle_adjuster.h)
  double ba_seconds = 0.0;
  double busy_seconds = 0.0;
};

class LocalMapper {
 public:
  LocalMapper(map::Map& map, LocalMapperParams params, bool threaded);
  ~LocalMapper();
  LocalMapper(const LocalMapper&) = delete;
  LocalMapper& operator=(const LocalMapper&) = delete;

  // Place recognition: each keyframe's bag of words is computed and indexed in `database` when
  // the keyframe is processed. Set before the first keyframe.
  void set_place_recognition(const place::Vocabulary* vocabulary, map::KeyFrameDatabase* database) {
    vocabulary_ = vocabulary;
    database_ = database;
  }
  // Called (in the mapping thread, map mutex not held) with each keyframe once processed and still
  // in the map: loop closing takes it from there. Set before the first keyframe.
  using KeyFrameCallback = std::function<void(map::KeyFrame*)>;
  void set_keyframe_callback(KeyFrameCallback callback) { keyframe_callback_ = std::move(callback); }
  // Where the thread's error goes (it stops at the first); without a sink, shutdown() rethrows it.
  // Set before the first keyframe.
  void set_error_sink(util::ThreadErrors* errors) { errors_ = errors; }
  // Called by tracking (which may hold the map mutex: only the queue's own lock is taken).
  void insert_keyframe(map::KeyFrame* kf);
  // Idle and ready for a keyframe (ORB-SLAM2's AcceptKeyFrames).
  [[nodiscard]] bool accepts_keyframes() const { return accepting_.load(); }
  [[nodiscard]] std::size_t queued() const;
  [[nodiscard]] const LocalMapperParams& params() const { return params_; }
  void interrupt_ba() { abort_ba_.store(true); }

  // Lock-step mode: processes every queued keyframe now, in the calling thread, which must not
  // hold the map mutex.
  void process_queued();
  // Processes what is queued and stops the thread. Idempotent.
  void shutdown();
  [[nodiscard]] LocalMapperStats stats() const;

 private:
  void run();
  void process(std::uint64_t keyframe_id);
  void process_new_keyframe(map::KeyFrame* kf);
  void cull_recent_map_points(map::KeyFrame* kf);
  void create_new_map_points(map::KeyFrame* kf);
  void search_in_neighbours(map::KeyFrame* kf);
  void cull_keyframes(map::KeyFrame* kf);
  [[nodiscard]] bool has_queued() const { return queued() > 0; }

  map::Map& map_;
  const LocalMapperParams params_;
  const bool threaded_;
  match::OrbMatcher matcher_;
  const place::Vocabulary* vocabulary_ = nullptr;
  map::KeyFrameDatabase* database_ = nullptr;
  KeyFrameCallback keyframe_callback_;
  std::list<map::MapPoint*> recent_points_;  // this thread only
  map::ReclamationMembership reclamation_;

  util::ThreadErrors own_errors_;
  util::ThreadErrors* errors_ = &own_errors_;
  util::WorkQueue<std::uint64_t> queue_;  // keyframe ids: one may be removed while queued
  std::atomic<bool> accepting_{true};
  std::atomic<bool> abort_ba_{false};
  mutable std::mutex stats_mutex_;
  LocalMapperStats stats_;
  std::thread thread_;
};

}  // namespace lrd::mapping
