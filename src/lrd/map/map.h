#pragma once
// The map: owner of every keyframe and map point. Objects that go bad leave the active sets but
// stay allocated until the map is destroyed, so pointers held by another thread (tracking's last
// frame, a queued keyframe) never dangle; ORB-SLAM2 leaks them for the same reason.
//
// One mutex guards the whole map: tracking holds it while it tracks a frame, local mapping while
// it performs each of its steps, and local BA only while it reads the problem and writes back.
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"

namespace lrd::map {

class Map {
 public:
  Map() = default;
  Map(const Map&) = delete;
  Map& operator=(const Map&) = delete;

  [[nodiscard]] std::mutex& mutex() { return mutex_; }

  KeyFrame* create_keyframe(const data::Frame& frame);
  MapPoint* create_map_point(const Eigen::Vector3d& position, KeyFrame* reference, std::uint64_t frame_id);
  // Called by set_bad(): drop from the active sets.
  void erase_keyframe(KeyFrame* kf) { keyframes_.erase(kf->id()); }
  void erase_map_point(MapPoint* mp) { points_.erase(mp->id()); }

  // Active objects in id order.
  [[nodiscard]] std::vector<KeyFrame*> keyframes() const;
  [[nodiscard]] std::vector<MapPoint*> map_points() const;
  [[nodiscard]] std::size_t keyframe_count() const { return keyframes_.size(); }
  [[nodiscard]] std::size_t map_point_count() const { return points_.size(); }
  [[nodiscard]] KeyFrame* first_keyframe() const {
    return keyframes_.empty() ? nullptr : keyframes_.begin()->second;
  }
  // Every keyframe ever created, including removed ones (for trajectory output).
  [[nodiscard]] KeyFrame* keyframe_by_creation(std::size_t i) const { return all_keyframes_[i].get(); }

  // Counts corrections of the whole map (loop closure, global BA merge). Local BA, which solves
  // without the lock, drops its result when this changed meanwhile: its poses predate the
  // correction and writing them back would undo it (ORB-SLAM2's mnBigChangeIdx).
  [[nodiscard]] std::uint64_t big_change_index() const { return big_change_index_; }
  void notify_big_change() { ++big_change_index_; }

  // Reset to an empty map (tracking lost right after initialization).
  void clear();

 private:
  std::mutex mutex_;
  std::vector<std::unique_ptr<KeyFrame>> all_keyframes_;
  std::vector<std::unique_ptr<MapPoint>> all_points_;
  std::map<std::uint64_t, KeyFrame*> keyframes_;
  std::map<std::uint64_t, MapPoint*> points_;
  std::uint64_t next_keyframe_id_ = 0;
  std::uint64_t next_point_id_ = 0;
  std::uint64_t big_change_index_ = 0;
};

}  // namespace lrd::map
