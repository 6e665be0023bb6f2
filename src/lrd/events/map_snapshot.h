#pragma once
// A copy of the sparse map at one moment, safe to keep and read on any thread.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "lrd/events/events.h"

namespace lrd::events {

struct MapPointSnapshot {
  std::uint64_t id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  std::vector<std::uint64_t> keyframes;  // the keyframes observing it
};

struct MapSnapshot {
  std::vector<KeyframePose> keyframes;
  std::vector<MapPointSnapshot> points;
};

}  // namespace lrd::events
