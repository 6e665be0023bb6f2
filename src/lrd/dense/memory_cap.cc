// The dense mapper's memory cap (dense.max_memory_mb, docs/dense-map.md): past it, the keyframe
// clouds the map has culled go first (other keyframes see what they saw), then the oldest, never
// the recent ones the free-space check still compares against.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <deque>
#include <vector>

#include "lrd/dense/dense_mapper.h"
#include "lrd/map/map.h"

namespace lrd::dense {

void DenseMapper::enforce_memory_cap() {
  // Only this thread changes stored_ and storage_, so it reads them without mutex_.
  const auto cap = static_cast<std::size_t>(params_.max_memory_mb * 1024.0 * 1024.0);
  if (cap == 0 || storage_.bytes <= cap) return;
  // stored_ ends with recent_'s keyframes, which the free-space check indexes from the back.
  const std::size_t evictable = stored_.size() - std::min(stored_.size(), recent_.size());
  std::vector<char> culled(evictable);
  {
    std::lock_guard lock(map_.mutex());
    for (std::size_t k = 0; k < evictable; ++k) culled[k] = map_.keyframe(stored_[k].keyframe_id) == nullptr;
  }
  // Culled keyframes first (others see what they saw: ORB-SLAM2's redundancy test), oldest first.
  std::vector<std::size_t> order(evictable);
  for (std::size_t k = 0; k < evictable; ++k) order[k] = k;
  std::stable_partition(order.begin(), order.end(), [&](std::size_t k) { return culled[k] != 0; });
  std::vector<char> drop(stored_.size(), 0);
  std::size_t bytes = storage_.bytes;
  DenseStorage dropped;
  for (std::size_t k : order) {
    if (bytes <= cap) break;
    drop[k] = 1;
    const std::size_t n = stored_[k].local->size();
    bytes -= n * kBytesPerPoint;
    dropped.points += n;
    ++dropped.evicted_keyframes;
    dropped.evicted_active += static_cast<std::size_t>(culled[k] == 0);
  }
  if (dropped.evicted_keyframes == 0) return;  // the newest alone are over the cap
  if (dropped.evicted_active > 0 && storage_.evicted_active == 0)
    spdlog::warn(
        "dense mapping: the keyframe clouds reached dense.max_memory_mb = {} MiB: the oldest are dropped",
        params_.max_memory_mb);
  std::lock_guard lock(mutex_);  // readers copy the clouds' pointers under it
  std::deque<Stored> kept;
  for (std::size_t k = 0; k < stored_.size(); ++k)
    if (drop[k] == 0) kept.push_back(std::move(stored_[k]));
  stored_.swap(kept);
  storage_.keyframes = stored_.size();
  storage_.points -= dropped.points;
  storage_.bytes = bytes;
  storage_.evicted_keyframes += dropped.evicted_keyframes;
  storage_.evicted_active += dropped.evicted_active;
}

}  // namespace lrd::dense
