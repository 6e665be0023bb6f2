#include "lrd/node/node_system.h"

#include "lrd/config/config.h"
#include "lrd/dynamic/dynamic_params.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/util/error.h"

namespace lrd::node {

namespace {

lrd::runner::RunOptions run_options(const NodeSettings& s) {
  lrd::runner::RunOptions o;
  if (!s.settings.empty()) o.settings = s.settings;
  if (!s.config.empty()) o.config = s.config;
  if (!s.mode.empty()) o.mode = s.mode;
  if (!s.segmenter.empty()) o.segmenter = s.segmenter;
  if (!s.segmenter_model.empty()) o.segmenter_model = s.segmenter_model;
  o.dense = s.dense;
  return o;  // no sequence folder: the default segmenter is the one for real data
}

}  // namespace

bool names_camera(const NodeSettings& settings) {
  if (!settings.settings.empty()) return true;
  return !settings.config.empty() && lrd::config::load_config(settings.config).camera_given;
}

NodeSystem make_system(const NodeSettings& settings,
                       const std::optional<lrd::io::SourceCamera>& camera_info) {
  const lrd::runner::RunOptions o = run_options(settings);
  NodeSystem n;
  lrd::config::Config cfg = lrd::runner::resolve_config(o, &n.camera_source);
  if (!names_camera(settings)) {
    if (!camera_info) throw lrd::Error("no camera: set ~settings or publish a camera_info");
    cfg.camera = lrd::runner::camera_from_source(*camera_info, cfg.camera);
    n.camera_source = camera_info->origin;
  }
  lrd::SystemOptions options;
  options.max_queued_frame_events = settings.max_queued_frame_events;
  options.yardstick = settings.yardstick;
  const lrd::SystemParams params = lrd::runner::configure_system(o, cfg);
  n.camera = cfg.camera;
  n.system = std::make_unique<lrd::System>(cfg, params, options);
  // An earlier run's map (an autosave after a crash): the first frames relocalize in it.
  if (!settings.load_map.empty()) n.system->load_map(settings.load_map);
  n.description = "mode " + lrd::dynamic::to_string(n.system->mode()) + ", segmentation " +
                  n.system->segmentation_description();
  return n;
}

void write_track_times(const std::filesystem::path& file, const std::vector<FrameTime>& frames) {
  std::vector<lrd::runner::FrameLog> log;
  log.reserve(frames.size());
  for (const FrameTime& f : frames) {
    const lrd::TrackResult& r = f.result;
    log.push_back({f.index, f.timestamp, r.state, r.timing, r.inliers, r.dynamic.mask_frame,
                   r.dynamic.mask_age, r.dynamic.geometric_keypoints});
  }
  lrd::runner::write_track_times(file, log);
}

}  // namespace lrd::node
