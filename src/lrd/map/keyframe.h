#pragma once
// A keyframe (ORB-SLAM2's KeyFrame): the features of a frame kept in the map, its pose, the map
// point behind each keypoint, and its place in the three graphs of the map: the covisibility
// graph (edge weight = map points seen by both), the spanning tree (each keyframe's parent is
// its most covisible earlier keyframe) and loop edges; together with strong covisibility edges
// (weight >= 100) they form the essential graph that loop closing optimizes.
//
// Poses are world-to-camera (T_cw). All access happens under Map::mutex() (see map_point.h).
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "lrd/data/frame.h"
#include "lrd/geometry/se3.h"
#include "lrd/map/by_id.h"

namespace lrd::map {

class Map;
class MapPoint;

class KeyFrame {
 public:
  // Takes over the frame's features, pose and map-point matches.
  KeyFrame(std::uint64_t id, const data::Frame& frame, Map* map);

  [[nodiscard]] std::uint64_t id() const { return id_; }
  [[nodiscard]] std::uint64_t frame_id() const { return frame_.id(); }
  [[nodiscard]] double timestamp() const { return frame_.timestamp(); }
  // Keypoints, descriptors, depths, grid search (the frame's images are not kept).
  [[nodiscard]] const data::Frame& features() const { return frame_; }
  [[nodiscard]] std::size_t size() const { return frame_.size(); }

  // Bag-of-words (place recognition): computed once when local mapping takes the keyframe.
  void compute_bow(const place::Vocabulary& vocabulary) { frame_.compute_bow(vocabulary); }
  [[nodiscard]] data::Frame::Words words(const place::Vocabulary& vocabulary) const {
    return frame_.words(vocabulary);
  }
  void set_words(data::Frame::Words words) { frame_.set_words(std::move(words)); }
  [[nodiscard]] const place::BowVector& bow() const { return frame_.bow; }
  [[nodiscard]] const place::FeatureVector& bow_features() const { return frame_.bow_features; }

  [[nodiscard]] const Eigen::Isometry3d& T_cw() const { return T_cw_; }
  [[nodiscard]] Eigen::Isometry3d T_wc() const { return T_cw_.inverse(); }
  [[nodiscard]] Eigen::Vector3d camera_center() const { return T_cw_.inverse().translation(); }
  void set_pose(const Eigen::Isometry3d& T_cw) { T_cw_ = geometry::orthonormalized(T_cw); }

  // --- map points, one slot per keypoint
  [[nodiscard]] const std::vector<MapPoint*>& map_points() const { return points_; }
  [[nodiscard]] MapPoint* map_point(std::size_t i) const { return points_[i]; }
  void add_map_point(MapPoint* mp, std::size_t i) { points_[i] = mp; }
  void erase_map_point(std::size_t i) { points_[i] = nullptr; }
  // Clears every slot holding `mp`, whether or not mp lists this keyframe among its observations
  // (tracking can match one point to two keypoints; a keyframe not yet mapped is not observed).
  void erase_map_point(const MapPoint* mp);
  // Good map points with at least `min_observations` (weighted) observations.
  [[nodiscard]] int tracked_map_points(int min_observations) const;
  // Depth of the q-quantile of the scene in front of the camera (q = 0.5: median).
  [[nodiscard]] double scene_depth_quantile(double q) const;

  // --- covisibility graph
  // Recomputes this keyframe's edges from its map points' observations (weight >= 15, or the
  // strongest one if none reaches it), updates the neighbours' edges, and, the first time,
  // attaches the keyframe to the spanning tree under its most covisible keyframe.
  void update_connections();
  void add_connection(KeyFrame* kf, int weight);
  void erase_connection(KeyFrame* kf);
  [[nodiscard]] int weight(KeyFrame* kf) const;
  // Neighbours by decreasing weight (ties by id), at most n.
  [[nodiscard]] std::vector<KeyFrame*> best_covisibles(std::size_t n) const;
  [[nodiscard]] std::vector<KeyFrame*> covisibles_with_weight(int min_weight) const;
  [[nodiscard]] const std::vector<KeyFrame*>& ordered_covisibles() const { return ordered_neighbours_; }
  [[nodiscard]] const std::vector<int>& ordered_weights() const { return ordered_weights_; }
  // Every edge with its weight (the ordered list may hold only the strong ones).
  [[nodiscard]] const std::map<KeyFrame*, int, ById>& connections() const { return connections_; }
  // Every keyframe sharing at least one map point with this one (weak links included), by id.
  [[nodiscard]] std::vector<KeyFrame*> connected_keyframes() const {
    std::vector<KeyFrame*> out;
    out.reserve(connections_.size());
    for (const auto& [kf, w] : connections_) out.push_back(kf);
    return out;
  }

  // --- spanning tree and loop edges (the essential graph)
  [[nodiscard]] KeyFrame* parent() const { return parent_; }
  [[nodiscard]] const std::set<KeyFrame*, ById>& children() const { return children_; }
  void change_parent(KeyFrame* parent);
  // A keyframe closing a loop is never removed (the loop edge would be lost, as ORB-SLAM2).
  void add_loop_edge(KeyFrame* kf) {
    loop_edges_.insert(kf);
    not_erase_ = true;
  }
  [[nodiscard]] const std::set<KeyFrame*, ById>& loop_edges() const { return loop_edges_; }
  // Tracking links: keyframes that consecutive frames were tracked against, this one and another
  // (the camera trajectory passes from one to the other between two frames). Edges of the loop
  // correction's essential graph, and what loop closing, global and local BA check their solutions
  // against (optim/odometry_change.h). By id, each with the other's pose relative to this one when
  // the link was made (T_this,other = T_this,w T_w,other: the odometry as tracked, which
  // corrections must not take the pair far from, one after another). Links both ways; a second
  // link of a pair keeps the first's pose. A removed keyframe's links go to its parent. Not saved
  // in map files.
  void add_tracking_link(KeyFrame* other);
  [[nodiscard]] const std::map<std::uint64_t, Eigen::Isometry3d>& tracking_links() const {
    return tracking_links_;
  }
  // Essential-graph neighbours: parent, children, loop edges and covisibles with weight >= min_weight.
  [[nodiscard]] std::vector<KeyFrame*> essential_neighbours(int min_weight = 100) const;

  // Removes the keyframe from the graphs and the map; its children are re-attached to the
  // spanning tree. Its pose relative to its parent is kept so that frames referring to it still
  // follow map corrections. Keyframe 0 (the map origin) is never removed.
  void set_bad();
  [[nodiscard]] bool is_bad() const { return bad_; }
  // Parent-relative pose T_c,parent recorded when the keyframe went bad (the map keeps it after the
  // keyframe is freed: Map::resolve_pose()).
  [[nodiscard]] const Eigen::Isometry3d& T_c_parent() const { return T_c_parent_; }
  // Heap and object bytes of this keyframe, for memory figures.
  [[nodiscard]] std::size_t memory_bytes() const;
  // Loop closing can protect a keyframe from culling while it works on it.
  void set_not_erase(bool v) { not_erase_ = v; }
  [[nodiscard]] bool not_erase() const { return not_erase_; }
  // Still to be attached to the spanning tree at its next connection update.
  [[nodiscard]] bool first_connection() const { return first_connection_; }

  // The graphs as a map file saved them (map/map_file.h); once, on a keyframe just restored.
  struct SavedGraph {
    std::map<KeyFrame*, int, ById> connections;
    std::vector<std::pair<KeyFrame*, int>> ordered;  // ordered_covisibles() with their weights
    KeyFrame* parent = nullptr;
    std::set<KeyFrame*, ById> loop_edges;
    bool not_erase = false;
    bool first_connection = false;
  };
  void restore_graph(SavedGraph graph);

  // Scratch marks (the frame / keyframe id of the last operation that touched it).
  std::uint64_t track_reference_for_frame = UINT64_MAX;
  // Points the frame being tracked shares with this keyframe, and the tracker's count they belong to.
  std::uint64_t track_count_for_frame = UINT64_MAX;
  int track_shared_points = 0;
  std::uint64_t fuse_target_for_kf = UINT64_MAX;
  std::uint64_t local_ba_for_kf = UINT64_MAX;
  std::uint64_t fixed_ba_for_kf = UINT64_MAX;
  std::uint64_t place_query_for = UINT64_MAX;  // keyframe database: the query that counted it
  int place_shared_words = 0;
  double place_score = 0.0;
  std::uint64_t loop_query_for_kf = UINT64_MAX;  // loop closing: corrected with this loop
  std::uint64_t global_ba_for = UINT64_MAX;      // global BA: the run that optimized it
  Eigen::Isometry3d T_cw_global_ba = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_cw_before_global_ba = Eigen::Isometry3d::Identity();

 private:
  void update_best_covisibles();

  std::uint64_t id_;
  data::Frame frame_;
  Eigen::Isometry3d T_cw_;
  std::vector<MapPoint*> points_;
  std::map<KeyFrame*, int, ById> connections_;
  std::vector<KeyFrame*> ordered_neighbours_;
  std::vector<int> ordered_weights_;
  bool first_connection_ = true;
  KeyFrame* parent_ = nullptr;
  std::set<KeyFrame*, ById> children_;
  std::set<KeyFrame*, ById> loop_edges_;
  std::map<std::uint64_t, Eigen::Isometry3d> tracking_links_;
  bool bad_ = false;
  bool not_erase_ = false;
  Eigen::Isometry3d T_c_parent_ = Eigen::Isometry3d::Identity();
  Map* map_;
};

}  // namespace lrd::map
