#include "lrd/map/map.h"

namespace lrd::map {

KeyFrame* Map::create_keyframe(const data::Frame& frame) {
  auto kf = std::make_unique<KeyFrame>(next_keyframe_id_++, frame, this);
  KeyFrame* raw = kf.get();
  all_keyframes_.push_back(std::move(kf));
  keyframes_.emplace(raw->id(), raw);
  return raw;
}

MapPoint* Map::create_map_point(const Eigen::Vector3d& position, KeyFrame* reference,
                                std::uint64_t frame_id) {
  auto mp = std::make_unique<MapPoint>(next_point_id_++, position, reference, frame_id, this);
  MapPoint* raw = mp.get();
  all_points_.push_back(std::move(mp));
  points_.emplace(raw->id(), raw);
  return raw;
}

std::vector<KeyFrame*> Map::keyframes() const {
  std::vector<KeyFrame*> out;
  out.reserve(keyframes_.size());
  for (const auto& [id, kf] : keyframes_) out.push_back(kf);
  return out;
}

std::vector<MapPoint*> Map::map_points() const {
  std::vector<MapPoint*> out;
  out.reserve(points_.size());
  for (const auto& [id, mp] : points_) out.push_back(mp);
  return out;
}

void Map::clear() {
  // Objects stay allocated (other threads may still hold pointers); only the active sets empty.
  keyframes_.clear();
  points_.clear();
}

}  // namespace lrd::map
