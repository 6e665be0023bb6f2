#pragma once
// A 3D landmark (ORB-SLAM2's MapPoint): world position, the keyframes observing it and through
// which keypoint, a representative descriptor (the medoid of its observations' descriptors), the
// mean viewing direction and the distance range over which ORB can re-detect it (scale
// invariance), used to predict the pyramid level and to reject implausible projections.
//
// Thread safety: every map object is read and written under Map::mutex() (tracking holds it for
// a whole frame, local mapping for each of its steps), so the objects themselves carry no locks.
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <opencv2/core.hpp>
#include <optional>

#include "lrd/map/by_id.h"

namespace lrd::map {

class KeyFrame;
class Map;

class MapPoint {
 public:
  MapPoint(std::uint64_t id, const Eigen::Vector3d& position, KeyFrame* reference,
           std::uint64_t first_frame_id, Map* map);

  [[nodiscard]] std::uint64_t id() const { return id_; }
  [[nodiscard]] const Eigen::Vector3d& position() const { return position_; }
  void set_position(const Eigen::Vector3d& p) { position_ = p; }
  [[nodiscard]] const Eigen::Vector3d& normal() const { return normal_; }  // mean viewing direction
  [[nodiscard]] const cv::Mat& descriptor() const { return descriptor_; }  // 1 x 32 CV_8U
  [[nodiscard]] KeyFrame* reference_keyframe() const { return reference_; }
  [[nodiscard]] std::uint64_t first_keyframe_id() const { return first_keyframe_id_; }
  [[nodiscard]] std::uint64_t first_frame_id() const { return first_frame_id_; }

  // Observations: keyframe -> keypoint index, ordered by keyframe id (deterministic iteration).
  using Observations = std::map<KeyFrame*, std::size_t, ById>;
  [[nodiscard]] const Observations& observations() const { return observations_; }
  // ORB-SLAM2's count: an observation with depth counts twice (it constrains the point alone).
  [[nodiscard]] int num_observations() const { return num_obs_; }
  void add_observation(KeyFrame* kf, std::size_t index);
  // Removes kf's observation; a point left with <= 2 (weighted) observations is set bad.
  void erase_observation(KeyFrame* kf);
  [[nodiscard]] bool is_in_keyframe(KeyFrame* kf) const { return observations_.count(kf) != 0; }
  [[nodiscard]] std::optional<std::size_t> index_in(KeyFrame* kf) const;

  // Removes the point from every keyframe observing it and from the map (kept alive by the map
  // until it is destroyed, so stale pointers held by other threads stay valid).
  void set_bad();
  [[nodiscard]] bool is_bad() const { return bad_; }
  // Merges this point into `other` (duplicate fusion): observations move over, this one goes bad.
  void replace(MapPoint* other);
  [[nodiscard]] MapPoint* replaced_by() const { return replaced_by_; }

  // Tracking statistics: frames where the point was predicted visible, and where it was matched.
  void increase_visible(int n = 1) { visible_ += n; }
  void increase_found(int n = 1) { found_ += n; }
  [[nodiscard]] float found_ratio() const {
    return static_cast<float>(found_) / static_cast<float>(visible_);
  }
  [[nodiscard]] int found() const { return found_; }
  [[nodiscard]] int visible() const { return visible_; }

  // The observation descriptor with the least median Hamming distance to the others.
  void compute_distinctive_descriptor();
  // Mean viewing direction and the scale-invariance distances, from the reference keyframe.
  void update_normal_and_depth();
  // Used after creation from one keyframe, before any other observation exists.
  void set_descriptor(const cv::Mat& d) { descriptor_ = d; }

  // The distances at which the reference keyframe's detection level maps to the finest and the
  // coarsest level.
  [[nodiscard]] float min_distance() const { return min_distance_; }
  [[nodiscard]] float max_distance() const { return max_distance_; }
  [[nodiscard]] float min_distance_invariance() const { return 0.8f * min_distance_; }
  [[nodiscard]] float max_distance_invariance() const { return 1.2f * max_distance_; }
  // Pyramid level at which a point at `distance` is expected to be detected.
  [[nodiscard]] int predict_scale(float distance, float log_scale_factor, int levels) const;
  // Heap and object bytes of this point, for memory figures.
  [[nodiscard]] std::size_t memory_bytes() const;

  // What a map file saved beyond position and observations (map/map_file.h), restored as is.
  struct SavedState {
    std::uint64_t first_keyframe_id = 0;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    cv::Mat descriptor;
    float min_distance = 0, max_distance = 0;
    int visible = 1, found = 1;
  };
  void restore_state(const SavedState& state);

  // Scratch state of tracking's local-map search (valid for the frame `last_frame_seen` etc.).
  struct TrackState {
    bool in_view = false;
    float proj_x = 0, proj_y = 0, proj_xr = -1;
    int scale_level = 0;
    float view_cos = 0;
    std::uint64_t last_frame_seen = UINT64_MAX;
    std::uint64_t local_for_frame = UINT64_MAX;
  } track;
  // Scratch marks of local mapping: the keyframe whose fusion / local BA last included it.
  std::uint64_t fuse_candidate_for_kf = UINT64_MAX;
  std::uint64_t local_ba_for_kf = UINT64_MAX;
  // Scratch marks of loop closing: the loop (its current keyframe's id) that moved the point, and
  // the keyframe whose correction it followed.
  std::uint64_t loop_corrected_for = UINT64_MAX;
  KeyFrame* loop_corrected_by = nullptr;

 private:
  std::uint64_t id_;
  std::uint64_t first_keyframe_id_;
  std::uint64_t first_frame_id_;
  Eigen::Vector3d position_;
  Eigen::Vector3d normal_ = Eigen::Vector3d::Zero();
  cv::Mat descriptor_;
  KeyFrame* reference_;
  Observations observations_;
  int num_obs_ = 0;
  int visible_ = 1, found_ = 1;
  float min_distance_ = 0, max_distance_ = 0;
  bool bad_ = false;
  MapPoint* replaced_by_ = nullptr;
  Map* map_;
};

}  // namespace lrd::map
