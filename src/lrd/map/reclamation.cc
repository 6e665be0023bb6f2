#include "lrd/map/reclamation.h"

#include <algorithm>
#include <limits>

#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"

namespace lrd::map {

Reclamation::Reclamation() = default;
Reclamation::~Reclamation() = default;

Reclamation::Participant Reclamation::join(std::string name) {
  std::lock_guard lock(mutex_);
  // A newcomer holds nothing yet: what was removed before it joined does not wait for it. The place
  // of one that left is taken again (a map saved every few seconds joins for each save).
  const Member member{std::move(name), true, ++epoch_};
  for (std::size_t p = 0; p < members_.size(); ++p)
    if (!members_[p].active) {
      members_[p] = member;
      return p;
    }
  members_.push_back(member);
  return members_.size() - 1;
}

void Reclamation::leave(Participant p) {
  std::lock_guard lock(mutex_);
  members_.at(p).active = false;
  collect();
}

void Reclamation::quiescent(Participant p) {
  std::lock_guard lock(mutex_);
  members_.at(p).seen = ++epoch_;
  collect();
}

void Reclamation::retire(std::unique_ptr<KeyFrame> kf) {
  std::lock_guard lock(mutex_);
  keyframes_.push_back({std::move(kf), epoch_});
}

void Reclamation::retire(std::unique_ptr<MapPoint> mp) {
  std::lock_guard lock(mutex_);
  points_.push_back({std::move(mp), epoch_});
}

ReclamationStats Reclamation::stats() const {
  std::lock_guard lock(mutex_);
  ReclamationStats s = stats_;
  s.waiting_keyframes = keyframes_.size();
  s.waiting_map_points = points_.size();
  return s;
}

void Reclamation::collect() {
  std::uint64_t oldest = std::numeric_limits<std::uint64_t>::max();
  for (const Member& m : members_)
    if (m.active) oldest = std::min(oldest, m.seen);
  // Both queues are in removal order, so what is safe is a prefix of each.
  while (!keyframes_.empty() && keyframes_.front().epoch < oldest) {
    keyframes_.pop_front();
    ++stats_.freed_keyframes;
  }
  while (!points_.empty() && points_.front().epoch < oldest) {
    points_.pop_front();
    ++stats_.freed_map_points;
  }
}

}  // namespace lrd::map
