#pragma once
// The map: owner of every keyframe and map point. Objects that go bad leave the active sets at
// once and are freed later, when no thread can still hold a pointer to them (reclamation.h).
// A removed keyframe leaves behind its pose relative to its parent (a few dozen bytes), so that
// frames and dense clouds that referred to it still follow every later correction of the map.
//
// One mutex guards the whole map: tracking holds it while it tracks a frame, local mapping while
// it performs each of its steps, and local BA only while it reads the problem and writes back.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "lrd/map/keyframe.h"
#include "lrd/map/map_memory.h"
#include "lrd/map/map_point.h"
#include "lrd/map/reclamation.h"

namespace lrd::map {

class Map {
 public:
  Map() = default;
  Map(const Map&) = delete;
  Map& operator=(const Map&) = delete;

  [[nodiscard]] std::mutex& mutex() { return mutex_; }

  KeyFrame* create_keyframe(const data::Frame& frame);
  MapPoint* create_map_point(const Eigen::Vector3d& position, KeyFrame* reference, std::uint64_t frame_id);
  // A map file's objects, with the ids they were saved with (map/map_file.h). Restored keyframes
  // count as taken by local mapping; later objects get ids after the largest restored one.
  KeyFrame* restore_keyframe(std::uint64_t id, const data::Frame& frame);
  MapPoint* restore_map_point(std::uint64_t id, const Eigen::Vector3d& position, KeyFrame* reference,
                              std::uint64_t first_frame_id);
  [[nodiscard]] std::uint64_t next_keyframe_id() const { return next_keyframe_id_; }
  [[nodiscard]] std::uint64_t next_map_point_id() const { return next_point_id_; }
  void restore_next_ids(std::uint64_t keyframe_id, std::uint64_t map_point_id);
  // Called by set_bad() / replace(): drop from the active sets and hand to reclamation. A removed
  // keyframe's pose link (its parent and pose relative to it, or its own pose without a parent)
  // is kept for resolve_pose().
  void erase_keyframe(KeyFrame* kf);
  void erase_map_point(MapPoint* mp);
  // Local mapping took the keyframe: from now on every map point in its slots observes it. Until
  // then a slot may hold a point matched by tracking that does not know the keyframe, so removing
  // that point cannot clear the slot by itself: erase_map_point() clears such slots instead.
  void keyframe_mapped(KeyFrame* kf);

  // Active objects in id order.
  [[nodiscard]] std::vector<KeyFrame*> keyframes() const;
  [[nodiscard]] std::vector<MapPoint*> map_points() const;
  [[nodiscard]] std::size_t keyframe_count() const { return keyframes_.size(); }
  [[nodiscard]] std::size_t map_point_count() const { return points_.size(); }
  [[nodiscard]] KeyFrame* first_keyframe() const {
    return keyframes_.empty() ? nullptr : keyframes_.begin()->second.get();
  }
  // The active keyframe with this id, or null (never created, or removed since).
  [[nodiscard]] KeyFrame* keyframe(std::uint64_t id) const;
  // The active keyframe nearest to keyframe `id` up the spanning tree as it was when the removed
  // ones left it (itself when active); null when there is none.
  [[nodiscard]] KeyFrame* nearest_active_keyframe(std::uint64_t id) const;
  // Current world-to-camera pose of a camera recorded as T_c_kf relative to keyframe `id`,
  // following the spanning tree past keyframes removed since. Call under mutex().
  [[nodiscard]] Eigen::Isometry3d resolve_pose(
      std::uint64_t keyframe_id, Eigen::Isometry3d T_c_kf = Eigen::Isometry3d::Identity()) const;

  // Counts corrections of the whole map (loop closure, global BA merge). Local BA, which solves
  // without the lock, drops its result when this changed meanwhile: its poses predate the
  // correction and writing them back would undo it (ORB-SLAM2's mnBigChangeIdx).
  [[nodiscard]] std::uint64_t big_change_index() const { return big_change_index_; }
  void notify_big_change() { ++big_change_index_; }

  [[nodiscard]] Reclamation& reclamation() { return reclamation_; }
  [[nodiscard]] MapMemory memory() const;  // call under mutex()

 private:
  struct PoseLink {
    std::uint64_t parent;  // kNoParent: T is the keyframe's own T_cw
    Eigen::Isometry3d T;   // T_c,parent
  };
  static constexpr std::uint64_t kNoParent = UINT64_MAX;

  std::mutex mutex_;
  std::map<std::uint64_t, std::unique_ptr<KeyFrame>> keyframes_;
  std::map<std::uint64_t, std::unique_ptr<MapPoint>> points_;
  std::unordered_map<std::uint64_t, PoseLink> removed_links_;
  std::vector<KeyFrame*> unmapped_;  // created, not yet taken by local mapping (a few at most)
  Reclamation reclamation_;
  std::uint64_t next_keyframe_id_ = 0;
  std::uint64_t next_point_id_ = 0;
  std::uint64_t big_change_index_ = 0;
};

}  // namespace lrd::map
