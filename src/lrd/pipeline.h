#pragma once
// The stages of one map (internal to lrd::System): the objects of the paper's Fig. 1 and how
// they are connected. System owns one; reset() replaces it with a fresh one.
//
//   frame -> DynamicFrontEnd (segmentation thread, mask carry-over) -> ORB extraction -> Tracker
//   Tracker -(geometry check)-> DynamicFrontEnd; Tracker -(keyframes)-> LocalMapper (thread)
//   LocalMapper -(processed keyframes)-> LoopCloser (thread, + global BA thread)
//   Tracker -(map crossings found by relocalization: suggested loops)-> LoopCloser
//   System -(new keyframes with images)-> DenseMapper (thread)
// Each thread reports its error to the shared util::ThreadErrors; callbacks from the threads
// become events on the EventPublisher.
#include <cstdint>
#include <memory>

#include "lrd/config/config.h"
#include "lrd/dense/dense_mapper.h"
#include "lrd/dynamic/dynamic_front_end.h"
#include "lrd/events/event_publisher.h"
#include "lrd/features/keypoint_undistorter.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/loop/loop_closer.h"
#include "lrd/map/keyframe_database.h"
#include "lrd/map/map.h"
#include "lrd/mapping/local_mapper.h"
#include "lrd/place/vocabulary.h"
#include "lrd/system_params.h"
#include "lrd/tracking/tracker.h"
#include "lrd/util/thread_errors.h"

namespace lrd {

struct Pipeline {
  // `generation`: which map of the system this is (0, then 1, 2, ... after each reset).
  Pipeline(const config::Config& config, const SystemParams& params, bool deterministic,
           const place::Vocabulary* vocabulary, util::ThreadErrors& errors, events::EventPublisher& publisher,
           std::uint32_t generation);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Lock-step mode: the background stages' work on what is queued, now, in this thread; an error
  // names its stage.
  void process_queued();
  // Finishes the queued work and joins the threads (first error rethrown by the caller).
  void shutdown();

  features::OrbExtractor extractor;
  features::KeypointUndistorter undistorter;
  dynamic::DynamicFrontEnd front_end;
  map::Map map;
  map::KeyFrameDatabase database;
  mapping::LocalMapper mapper;
  tracking::Tracker tracker;
  std::unique_ptr<loop::LoopCloser> loop_closer;  // after `mapper`: destroyed first
  std::unique_ptr<dense::DenseMapper> dense;      // before `map` is destroyed: it reads keyframe poses
  bool shut_down = false;
  const std::uint32_t generation;

 private:
  void publish_map_changed(std::uint64_t keyframe_id);
  void publish_loop(const loop::LoopEvent& loop);
  events::EventPublisher& publisher_;
};

}  // namespace lrd
