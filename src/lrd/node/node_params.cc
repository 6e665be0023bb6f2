#include "lrd/node/node_params.h"

#include <fmt/format.h>

#include "lrd/util/error.h"

namespace lrd::node {

NodeParams NodeParams::from(const ParamReader& r) {
  NodeParams p;
  p.param_prefix = r.display("");
  r.get("rgb_topic", p.rgb_topic);
  r.get("depth_topic", p.depth_topic);
  r.get("camera_info_topic", p.camera_info_topic);
  r.get("settings", p.system.settings);
  r.get("config", p.system.config);
  r.get("mode", p.system.mode);
  r.get("segmenter", p.system.segmenter);
  r.get("segmenter_model", p.system.segmenter_model);
  r.get("dense", p.system.dense);
  r.get("yardstick", p.system.yardstick);
  r.get("map_frame", p.publish.map_frame);
  r.get("camera_frame", p.publish.camera_frame);
  r.get("world_frame", p.publish.world_frame);
  r.get("queue_size", p.queue_size);
  r.get("max_pair_dt", p.max_pair_dt);
  r.get("autosave", p.autosave_s);
  r.get("load_map", p.system.load_map);
  std::string out = p.output_dir.string();
  r.get("output_dir", out);
  p.output_dir = out;
  if (p.queue_size < 1 || p.queue_size > 1000)
    throw Error(fmt::format("{} must be 1..1000, got {}", r.display("queue_size"), p.queue_size));
  if (!(p.max_pair_dt > 0.0 && p.max_pair_dt <= 1.0))
    throw Error(fmt::format("{} must be in (0, 1] s, got {}", r.display("max_pair_dt"), p.max_pair_dt));
  if (!(p.autosave_s >= 0.0))
    throw Error(fmt::format("{} must be a number of seconds >= 0 (0: off), got {}", r.display("autosave"),
                            p.autosave_s));
  if (p.publish.map_frame.empty()) throw Error(r.display("map_frame") + " must not be empty");
  if (p.output_dir.empty()) throw Error(r.display("output_dir") + " must not be empty");
  return p;
}

}  // namespace lrd::node
