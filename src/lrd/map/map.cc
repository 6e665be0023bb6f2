#include "lrd/map/map.h"

#include <algorithm>
#include <string>

#include "lrd/util/error.h"

namespace lrd::map {

KeyFrame* Map::create_keyframe(const data::Frame& frame) {
  auto kf = std::make_unique<KeyFrame>(next_keyframe_id_++, frame, this);
  KeyFrame* raw = kf.get();
  keyframes_.emplace(raw->id(), std::move(kf));
  unmapped_.push_back(raw);
  return raw;
}

MapPoint* Map::create_map_point(const Eigen::Vector3d& position, KeyFrame* reference,
                                std::uint64_t frame_id) {
  auto mp = std::make_unique<MapPoint>(next_point_id_++, position, reference, frame_id, this);
  MapPoint* raw = mp.get();
  points_.emplace(raw->id(), std::move(mp));
  return raw;
}

KeyFrame* Map::restore_keyframe(std::uint64_t id, const data::Frame& frame) {
  auto kf = std::make_unique<KeyFrame>(id, frame, this);
  KeyFrame* raw = kf.get();
  if (!keyframes_.emplace(id, std::move(kf)).second)
    throw Error("map: keyframe " + std::to_string(id) + " twice");
  next_keyframe_id_ = std::max(next_keyframe_id_, id + 1);
  return raw;
}

MapPoint* Map::restore_map_point(std::uint64_t id, const Eigen::Vector3d& position, KeyFrame* reference,
                                 std::uint64_t first_frame_id) {
  auto mp = std::make_unique<MapPoint>(id, position, reference, first_frame_id, this);
  MapPoint* raw = mp.get();
  if (!points_.emplace(id, std::move(mp)).second)
    throw Error("map: map point " + std::to_string(id) + " twice");
  next_point_id_ = std::max(next_point_id_, id + 1);
  return raw;
}

void Map::restore_next_ids(std::uint64_t keyframe_id, std::uint64_t map_point_id) {
  next_keyframe_id_ = std::max(next_keyframe_id_, keyframe_id);
  next_point_id_ = std::max(next_point_id_, map_point_id);
}

void Map::keyframe_mapped(KeyFrame* kf) {
  std::erase(unmapped_, kf);
}

void Map::erase_keyframe(KeyFrame* kf) {
  auto node = keyframes_.extract(kf->id());
  if (node.empty()) return;
  keyframe_mapped(kf);
  const KeyFrame* parent = kf->parent();
  removed_links_.emplace(kf->id(), parent != nullptr ? PoseLink{parent->id(), kf->T_c_parent()}
                                                     : PoseLink{kNoParent, kf->T_cw()});
  reclamation_.retire(std::move(node.mapped()));
}

void Map::erase_map_point(MapPoint* mp) {
  auto node = points_.extract(mp->id());
  if (node.empty()) return;
  for (KeyFrame* kf : unmapped_) kf->erase_map_point(mp);
  reclamation_.retire(std::move(node.mapped()));
}

std::vector<KeyFrame*> Map::keyframes() const {
  std::vector<KeyFrame*> out;
  out.reserve(keyframes_.size());
  for (const auto& [id, kf] : keyframes_) out.push_back(kf.get());
  return out;
}

std::vector<MapPoint*> Map::map_points() const {
  std::vector<MapPoint*> out;
  out.reserve(points_.size());
  for (const auto& [id, mp] : points_) out.push_back(mp.get());
  return out;
}

KeyFrame* Map::keyframe(std::uint64_t id) const {
  const auto it = keyframes_.find(id);
  return it == keyframes_.end() ? nullptr : it->second.get();
}

KeyFrame* Map::nearest_active_keyframe(std::uint64_t id) const {
  for (;;) {
    if (KeyFrame* kf = keyframe(id)) return kf;
    const auto link = removed_links_.find(id);
    if (link == removed_links_.end() || link->second.parent == kNoParent) return nullptr;
    id = link->second.parent;
  }
}

Eigen::Isometry3d Map::resolve_pose(std::uint64_t keyframe_id, Eigen::Isometry3d T_c_kf) const {
  // The parent of a removed keyframe may have been removed later: follow the links up to an
  // active keyframe (keyframe 0 never leaves) or a removed one without a parent.
  for (;;) {
    if (const KeyFrame* kf = keyframe(keyframe_id)) return T_c_kf * kf->T_cw();
    const auto link = removed_links_.find(keyframe_id);
    if (link == removed_links_.end()) return T_c_kf;  // never created: no better answer
    if (link->second.parent == kNoParent) return T_c_kf * link->second.T;
    T_c_kf = T_c_kf * link->second.T;
    keyframe_id = link->second.parent;
  }
}

MapMemory Map::memory() const {
  MapMemory m;
  m.keyframes = keyframes_.size();
  m.map_points = points_.size();
  for (const auto& [id, kf] : keyframes_) m.keyframe_bytes += kf->memory_bytes();
  for (const auto& [id, mp] : points_) m.map_point_bytes += mp->memory_bytes();
  m.removed_keyframe_links = removed_links_.size();
  // An unordered_map node: the value, the key's hash link and the allocator's header.
  m.link_bytes =
      removed_links_.size() * (sizeof(std::pair<const std::uint64_t, PoseLink>) + 2 * sizeof(void*)) +
      removed_links_.bucket_count() * sizeof(void*);
  m.reclamation = reclamation_.stats();
  return m;
}

}  // namespace lrd::map
