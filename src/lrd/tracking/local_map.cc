#include "lrd/tracking/local_map.h"

#include <algorithm>

#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/map/map_point.h"
#include "lrd/match/frustum.h"

namespace lrd::tracking {

namespace {
// Calls visit(point) for each map point the frame matched that is still good; a match to a point
// since culled or fused away is dropped from the frame.
template <typename Visit>
void for_each_good_match(data::Frame& frame, Visit visit) {
  for (std::size_t i = 0; i < frame.size(); ++i) {
    map::MapPoint* mp = frame.map_points[i];
    if (mp == nullptr) continue;
    if (mp->is_bad()) {
      frame.map_points[i] = nullptr;
      continue;
    }
    visit(mp);
  }
}
}  // namespace

LocalMap::LocalMap() : matcher_({0.8f, false}) {}

map::KeyFrame* LocalMap::update(data::Frame& frame, std::uint64_t tag, std::size_t max_keyframes) {
  map::KeyFrame* best = update_keyframes(frame, tag, max_keyframes);
  update_points(tag);
  return best;
}

map::KeyFrame* LocalMap::update_keyframes(data::Frame& frame, std::uint64_t tag, std::size_t max_keyframes) {
  // Keyframes sharing points with the frame, by number of shared points: counted on the keyframes
  // themselves rather than in a map rebuilt every frame, then taken in id order.
  const std::uint64_t count_tag = ++sharing_count_pass_;
  std::vector<map::KeyFrame*>& sharing = sharing_;
  sharing.clear();
  for_each_good_match(frame, [&](map::MapPoint* mp) {
    for (const auto& [kf, idx] : mp->observations()) {
      if (kf->track_count_for_frame != count_tag) {
        kf->track_count_for_frame = count_tag;
        kf->track_shared_points = 0;
        sharing.push_back(kf);
      }
      ++kf->track_shared_points;
    }
  });
  if (sharing.empty()) return nullptr;
  std::sort(sharing.begin(), sharing.end(), map::ById{});
  std::erase_if(sharing, [](const map::KeyFrame* kf) { return kf->is_bad(); });
  // At most max_keyframes of them, those sharing the most (where laps pile up keyframes over the
  // same room, every one sharing a few points would enter, and tracking's cost would grow with the
  // time spent there: bench/results/scale.md); kept in id order, as below the cap.
  if (sharing.size() > max_keyframes) {
    std::stable_sort(sharing.begin(), sharing.end(), [](const map::KeyFrame* a, const map::KeyFrame* b) {
      return a->track_shared_points > b->track_shared_points;
    });
    sharing.resize(max_keyframes);
    std::sort(sharing.begin(), sharing.end(), map::ById{});
  }
  keyframes_.clear();
  map::KeyFrame* best = nullptr;
  int best_count = 0;
  for (map::KeyFrame* kf : sharing) {
    if (kf->track_shared_points > best_count) {
      best_count = kf->track_shared_points;
      best = kf;
    }
    keyframes_.push_back(kf);
    kf->track_reference_for_frame = tag;
  }
  // Plus some neighbours of those: best covisibles, a child and the parent.
  const std::size_t first_order = keyframes_.size();
  auto try_add = [&](map::KeyFrame* kf) {
    if (kf == nullptr || kf->is_bad() || kf->track_reference_for_frame == tag) return false;
    kf->track_reference_for_frame = tag;
    keyframes_.push_back(kf);
    return true;
  };
  for (std::size_t i = 0; i < first_order && keyframes_.size() < max_keyframes; ++i) {
    map::KeyFrame* kf = keyframes_[i];
    for (map::KeyFrame* n : kf->best_covisibles(10))
      if (try_add(n)) break;
    for (map::KeyFrame* c : kf->children())
      if (try_add(c)) break;
    try_add(kf->parent());
  }
  return best;
}

void LocalMap::update_points(std::uint64_t tag) {
  points_.clear();
  for (map::KeyFrame* kf : keyframes_) {
    for (map::MapPoint* mp : kf->map_points()) {
      if (mp == nullptr || mp->is_bad() || mp->track.local_for_frame == tag) continue;
      mp->track.local_for_frame = tag;
      points_.push_back(mp);
    }
  }
}

int LocalMap::search(data::Frame& frame, std::uint64_t tag, float radius) {
  for_each_good_match(frame, [&](map::MapPoint* mp) {
    mp->increase_visible();
    mp->track.last_frame_seen = tag;
    mp->track.in_view = false;
  });
  int to_match = 0;
  for (map::MapPoint* mp : points_) {
    if (mp->track.last_frame_seen == tag || mp->is_bad()) {
      if (mp->track.last_frame_seen != tag) mp->track.in_view = false;
      continue;
    }
    if (!match::mark_for_projection_search(frame, *mp)) continue;
    mp->increase_visible();
    ++to_match;
  }
  if (to_match == 0) return 0;
  return matcher_.search_by_projection(frame, points_, radius);
}

void LocalMap::start(map::KeyFrame* first, std::vector<map::MapPoint*> points) {
  keyframes_ = {first};
  points_ = std::move(points);
}

void LocalMap::drop_removed() {
  std::erase_if(keyframes_, [](const map::KeyFrame* kf) { return kf->is_bad(); });
  std::erase_if(points_, [](const map::MapPoint* mp) { return mp->is_bad(); });
}

void LocalMap::restore(Contents contents) {
  keyframes_ = std::move(contents.keyframes);
  points_ = std::move(contents.points);
}

}  // namespace lrd::tracking
