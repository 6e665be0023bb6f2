#pragma once
// The `mapping` section of the config, typed.
#include "lrd/config/node_reader.h"
#include "lrd/mapping/keyframe_culling.h"
#include "lrd/optim/local_bundle_adjuster.h"

namespace lrd::mapping {

struct LocalMapperParams {
  int triangulation_neighbours = 10;  // covisible keyframes searched for new points
  int fuse_neighbours = 10;           // first- and second-order neighbours for duplicate fusion
  int fuse_second_neighbours = 5;
  bool local_ba = true;
  optim::LocalBundleAdjustmentParams ba;
  bool keyframe_culling = true;
  KeyFrameCullingParams culling;
  int max_queued = 3;  // tracking stops proposing keyframes beyond this queue length

  // Reads the `mapping` section of the config (and finishes it).
  static LocalMapperParams from_config(config::NodeReader reader);
};

}  // namespace lrd::mapping
