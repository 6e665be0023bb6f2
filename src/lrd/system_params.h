#pragma once
// Every module's parameters, read once from the config (each section by its module's own
// from_config, which checks its keys with file:line errors) with the command line's overrides
// applied. The modules take these typed structs; nothing reads a config section twice.
#include <filesystem>
#include <optional>

#include "lrd/config/config.h"
#include "lrd/dense/dense_params.h"
#include "lrd/dynamic/dynamic_params.h"
#include "lrd/loop/loop_closer.h"
#include "lrd/mapping/local_mapper.h"
#include "lrd/occupancy/occupancy_params.h"
#include "lrd/segmentation/segmentation_params.h"
#include "lrd/tracking/tracker_params.h"

namespace lrd {

struct SystemOptions {
  // Local mapping in lock-step after each keyframe, in the tracking thread: two runs over the same
  // input give bit-identical trajectories (slower: tracking waits for mapping).
  // Forces the segmentation schedule to sync (the async one depends on thread timing).
  bool deterministic = false;
  // Replace what the config's `dynamic` / `segmentation` sections say (the CLI's --mode and
  // --segmenter).
  std::optional<dynamic::DynamicMode> mode;
  std::optional<segmentation::SegmentationParams> segmentation;
  // Replaces the config's dense.enabled (the CLI's --dense): background repair and the dense map.
  std::optional<bool> dense;
  // Replaces the config's occupancy.enabled (the CLI's --occupancy, which implies --dense).
  std::optional<bool> occupancy;
  // Replaces the config's loop_closing.enabled (the CLI's --no-loop-closing) and vocabulary.
  std::optional<bool> loop_closing;
  std::optional<std::filesystem::path> vocabulary;
  // Track against the map load_map() loaded without adding to it (the CLI's --localization-only).
  bool localization_only = false;
  // A live viewer's bound on queued frame events (0: every frame is delivered).
  std::size_t max_queued_frame_events = 0;
  // Benchmarks: time OpenCV's ORB (the yardstick Y, util/yardstick.h) on each frame's
  // grey image in the tracking thread, right after our own extraction, so that Y and the work it
  // divides share the machine's state and the other threads' competition. FrameTiming::yardstick;
  // not in the frame's total.
  bool yardstick = false;
};

struct SystemParams {
  tracking::TrackerParams tracking;
  mapping::LocalMapperParams mapping;
  dynamic::DynamicParams dynamic;
  segmentation::SegmentationParams segmentation;
  loop::LoopClosingParams loop_closing;
  dense::DenseParams dense;
  occupancy::OccupancyParams occupancy;  // built from the dense stage's keyframes

  // Reads every section of `config` once, then applies `options`' overrides.
  [[nodiscard]] static SystemParams from_config(const config::Config& config,
                                                const SystemOptions& options = {});
};

}  // namespace lrd
