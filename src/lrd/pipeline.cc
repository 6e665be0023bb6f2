#include "lrd/pipeline.h"

#include <fmt/format.h>

#include <mutex>

#include "lrd/map/keyframe.h"
#include "lrd/util/error.h"
#include "lrd/util/exception_message.h"

namespace lrd {

namespace {
// Runs one stage's lock-step work; its error names the stage, as a thread's would.
template <class Work>
void run_stage(const char* stage, Work&& work) {
  try {
    work();
  } catch (...) {
    throw Error(fmt::format("{} thread: {}", stage, util::exception_message(std::current_exception())));
  }
}
}  // namespace

Pipeline::Pipeline(const config::Config& cfg, const SystemParams& p, bool deterministic,
                   const place::Vocabulary* vocabulary, util::ThreadErrors& errors,
                   events::EventPublisher& publisher, std::uint32_t map_generation)
    : extractor(cfg.features),
      undistorter(cfg.camera),
      front_end(p.dynamic, p.segmentation, cfg.camera),
      mapper(map, p.mapping, !deterministic),
      tracker(map, mapper, p.tracking),
      generation(map_generation),
      publisher_(publisher) {
  mapper.set_error_sink(&errors);
  tracker.set_moving_point_check(front_end.moving_point_check());
  // Place recognition: relocalization always, loop closing unless switched off.
  if (vocabulary != nullptr) {
    tracker.set_place_recognition(vocabulary, &database);
    mapper.set_place_recognition(vocabulary, &database);
    if (p.loop_closing.enabled) {
      loop_closer = std::make_unique<loop::LoopCloser>(map, database, mapper, p.loop_closing, !deterministic);
      loop_closer->set_error_sink(&errors);
      loop_closer->set_loop_callback([this](const loop::LoopEvent& e) { publish_loop(e); });
      tracker.set_crossing_callback([this](const tracking::MapCrossing& c) {
        loop_closer->suggest_loop({c.lost_keyframe_id, c.found_keyframe_id, c.T_cw_lost_keyframe});
      });
    }
  }
  mapper.set_keyframe_callback([this](map::KeyFrame* kf) {
    if (loop_closer) loop_closer->insert_keyframe(kf);
    publish_map_changed(kf->id());
  });
  if (p.dense.enabled) {
    dense = std::make_unique<dense::DenseMapper>(map, cfg.camera, p.dense, !deterministic);
    dense->set_error_sink(&errors);
    dense->set_update_callback([this](double timestamp, std::size_t keyframes, const dense::RgbdView& view,
                                      const dense::RepairResult* repair) {
      if (!publisher_.has_subscribers()) return;
      events::DenseMapUpdated e;
      e.map = generation;
      e.timestamp = timestamp;
      e.keyframes = keyframes;
      e.keyframe = view;
      if (repair != nullptr) {
        e.dynamic_pixels = static_cast<std::size_t>(repair->dynamic_pixels);
        e.filled_pixels = static_cast<std::size_t>(repair->filled_pixels);
        e.repair = *repair;
      }
      publisher_.publish(std::move(e));
    });
  }
}

Pipeline::~Pipeline() {
  try {
    shutdown();
  } catch (...) {  // the owner reports errors through its util::ThreadErrors
  }
}

void Pipeline::publish_map_changed(std::uint64_t keyframe_id) {
  if (!publisher_.has_subscribers()) return;
  events::MapChanged e;
  e.map = generation;
  e.keyframe_id = keyframe_id;
  {
    std::lock_guard lock(map.mutex());
    e.keyframes = map.keyframe_count();
    e.map_points = map.map_point_count();
  }
  const mapping::LocalMapperStats s = mapper.stats();
  e.culled_keyframes = s.culled_keyframes;
  e.triangulated_points = s.triangulated_points;
  publisher_.publish(std::move(e));
}

void Pipeline::publish_loop(const loop::LoopEvent& loop) {
  if (!publisher_.has_subscribers()) return;
  events::LoopClosed e{generation,
                       loop.frame_id,
                       loop.timestamp,
                       loop.keyframe_id,
                       loop.loop_keyframe_id,
                       loop.inliers,
                       loop.correction_m,
                       {}};
  {
    std::lock_guard lock(map.mutex());
    for (const map::KeyFrame* kf : map.keyframes())
      e.corrected.push_back({kf->id(), kf->timestamp(), kf->T_wc()});
  }
  publisher_.publish(std::move(e));
}

void Pipeline::process_queued() {
  run_stage("local mapping", [this] { mapper.process_queued(); });
  if (loop_closer) run_stage("loop closing", [this] { loop_closer->process_queued(); });
  if (dense) run_stage("dense mapping", [this] { dense->process_queued(); });
}

void Pipeline::shutdown() {
  if (shut_down) return;
  shut_down = true;
  // Every stage stops, even after another's error; the first error is rethrown.
  std::exception_ptr first;
  const auto stop = [&first](const char* stage, auto&& work) {
    try {
      run_stage(stage, work);
    } catch (...) {
      if (!first) first = std::current_exception();
    }
  };
  stop("segmentation", [this] { front_end.shutdown(); });
  stop("local mapping", [this] { mapper.shutdown(); });
  if (loop_closer) stop("loop closing", [this] { loop_closer->shutdown(); });
  if (dense) stop("dense mapping", [this] { dense->shutdown(); });
  if (first) std::rethrow_exception(first);
}

}  // namespace lrd
