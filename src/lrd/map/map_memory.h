#pragma once
// What the map holds in memory, for benchmarks and reports (Map::memory(), System::map_memory()).
#include <cstddef>

#include "lrd/map/reclamation.h"

namespace lrd::map {

struct MapMemory {
  std::size_t keyframes = 0;   // active
  std::size_t map_points = 0;  // active
  // Approximate bytes of the active objects: the objects and the heap data they own (features,
  // descriptors, grid, bag of words, graph edges, observations).
  std::size_t keyframe_bytes = 0;
  std::size_t map_point_bytes = 0;
  std::size_t removed_keyframe_links = 0;  // pose links left by removed keyframes
  std::size_t link_bytes = 0;
  ReclamationStats reclamation;  // freed so far, and removed but still waiting
};

}  // namespace lrd::map
