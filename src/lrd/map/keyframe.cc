#include "lrd/map/keyframe.h"

#include <algorithm>

#include "lrd/map/map.h"
#include "lrd/map/map_point.h"

namespace lrd::map {

namespace {
constexpr int kCovisibilityThreshold = 15;  // ORB-SLAM2: an edge needs 15 shared map points
}

KeyFrame::KeyFrame(std::uint64_t id, const data::Frame& frame, Map* map)
    : id_(id), frame_(frame), T_cw_(frame.T_cw()), points_(frame.map_points), map_(map) {
  // A point already removed would never clear its slot here (it does not observe this keyframe).
  for (std::size_t i = 0; i < points_.size(); ++i)
    if (frame.outliers[i] || (points_[i] != nullptr && points_[i]->is_bad())) points_[i] = nullptr;
  // Matches the last pose optimization called outliers stay (as ORB-SLAM2): local BA, with more
  // views, decides on them. The keyframe's own copy of the frame does not track anything.
  frame_.map_points.clear();
  frame_.outliers.clear();
  // The dynamic mask (a full image) and the removed keypoints serve viewers and the dense map,
  // which get their own copies: a keyframe holding them would keep ~300 KB per keyframe alive.
  frame_.map_points.shrink_to_fit();
  frame_.outliers.shrink_to_fit();
  frame_.dynamic_mask.release();
  frame_.removed_keypoints = {};
}

std::size_t KeyFrame::memory_bytes() const {
  constexpr std::size_t kNode = 4 * sizeof(void*);  // a std::map / std::set node's links
  return sizeof(KeyFrame) + frame_.memory_bytes() + points_.capacity() * sizeof(MapPoint*) +
         connections_.size() * (sizeof(std::pair<KeyFrame* const, int>) + kNode) +
         ordered_neighbours_.capacity() * sizeof(KeyFrame*) + ordered_weights_.capacity() * sizeof(int) +
         (children_.size() + loop_edges_.size()) * (sizeof(KeyFrame*) + kNode) +
         tracking_links_.size() * (sizeof(std::pair<const std::uint64_t, Eigen::Isometry3d>) + kNode);
}

void KeyFrame::add_tracking_link(KeyFrame* other) {
  if (other == this) return;
  const Eigen::Isometry3d T_this_other = T_cw_ * other->T_wc();
  tracking_links_.emplace(other->id_, T_this_other);
  other->tracking_links_.emplace(id_, T_this_other.inverse());
}

void KeyFrame::erase_map_point(const MapPoint* mp) {
  for (MapPoint*& slot : points_)
    if (slot == mp) slot = nullptr;
}

int KeyFrame::tracked_map_points(int min_observations) const {
  int n = 0;
  for (MapPoint* mp : points_)
    if (mp != nullptr && !mp->is_bad() && mp->num_observations() >= min_observations) ++n;
  return n;
}

double KeyFrame::scene_depth_quantile(double q) const {
  std::vector<double> depths;
  for (MapPoint* mp : points_)
    if (mp != nullptr && !mp->is_bad()) depths.push_back((T_cw_ * mp->position()).z());
  if (depths.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(depths.size() - 1));
  std::nth_element(depths.begin(), depths.begin() + static_cast<long>(k), depths.end());
  return depths[k];
}

void KeyFrame::add_connection(KeyFrame* kf, int weight) {
  auto [it, inserted] = connections_.emplace(kf, weight);
  if (!inserted) {
    if (it->second == weight) return;
    it->second = weight;
  }
  update_best_covisibles();
}

void KeyFrame::erase_connection(KeyFrame* kf) {
  if (connections_.erase(kf) != 0) update_best_covisibles();
}

int KeyFrame::weight(KeyFrame* kf) const {
  const auto it = connections_.find(kf);
  return it == connections_.end() ? 0 : it->second;
}

void KeyFrame::update_best_covisibles() {
  std::vector<std::pair<int, KeyFrame*>> pairs;
  pairs.reserve(connections_.size());
  for (const auto& [kf, w] : connections_) pairs.emplace_back(w, kf);
  std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second->id() < b.second->id();
  });
  ordered_neighbours_.clear();
  ordered_weights_.clear();
  for (const auto& [w, kf] : pairs) {
    ordered_neighbours_.push_back(kf);
    ordered_weights_.push_back(w);
  }
}

std::vector<KeyFrame*> KeyFrame::best_covisibles(std::size_t n) const {
  const std::size_t k = std::min(n, ordered_neighbours_.size());
  return {ordered_neighbours_.begin(), ordered_neighbours_.begin() + static_cast<long>(k)};
}

std::vector<KeyFrame*> KeyFrame::covisibles_with_weight(int min_weight) const {
  std::vector<KeyFrame*> out;
  for (std::size_t i = 0; i < ordered_neighbours_.size() && ordered_weights_[i] >= min_weight; ++i)
    out.push_back(ordered_neighbours_[i]);
  return out;
}

void KeyFrame::update_connections() {
  std::map<KeyFrame*, int, ById> counter;
  for (MapPoint* mp : points_) {
    if (mp == nullptr || mp->is_bad()) continue;
    for (const auto& [kf, idx] : mp->observations())
      if (kf != this && !kf->is_bad()) ++counter[kf];
  }
  if (counter.empty()) return;

  KeyFrame* strongest = nullptr;
  int max_weight = 0;
  bool any = false;
  for (const auto& [kf, w] : counter) {
    if (w > max_weight) {
      max_weight = w;
      strongest = kf;
    }
    if (w >= kCovisibilityThreshold) {
      kf->add_connection(this, w);
      any = true;
    }
  }
  if (!any) strongest->add_connection(this, max_weight);

  // Own edges: all counts (as ORB-SLAM2), ordered list restricted to strong ones.
  connections_ = counter;
  std::vector<std::pair<int, KeyFrame*>> pairs;
  for (const auto& [kf, w] : counter)
    if (w >= kCovisibilityThreshold || (!any && kf == strongest)) pairs.emplace_back(w, kf);
  std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second->id() < b.second->id();
  });
  ordered_neighbours_.clear();
  ordered_weights_.clear();
  for (const auto& [w, kf] : pairs) {
    ordered_neighbours_.push_back(kf);
    ordered_weights_.push_back(w);
  }

  if (first_connection_ && id_ != 0 && !ordered_neighbours_.empty()) {
    parent_ = ordered_neighbours_.front();
    parent_->children_.insert(this);
    first_connection_ = false;
  }
}

void KeyFrame::restore_graph(SavedGraph graph) {
  connections_ = std::move(graph.connections);
  ordered_neighbours_.clear();
  ordered_weights_.clear();
  for (const auto& [kf, w] : graph.ordered) {
    ordered_neighbours_.push_back(kf);
    ordered_weights_.push_back(w);
  }
  loop_edges_ = std::move(graph.loop_edges);
  not_erase_ = graph.not_erase;
  first_connection_ = graph.first_connection;
  change_parent(graph.parent);
}

void KeyFrame::change_parent(KeyFrame* parent) {
  if (parent_ != nullptr) parent_->children_.erase(this);
  parent_ = parent;
  if (parent_ != nullptr) parent_->children_.insert(this);
}

std::vector<KeyFrame*> KeyFrame::essential_neighbours(int min_weight) const {
  std::set<KeyFrame*, ById> out(children_.begin(), children_.end());
  if (parent_ != nullptr) out.insert(parent_);
  out.insert(loop_edges_.begin(), loop_edges_.end());
  for (KeyFrame* kf : covisibles_with_weight(min_weight)) out.insert(kf);
  return {out.begin(), out.end()};
}

void KeyFrame::set_bad() {
  if (id_ == 0 || bad_ || not_erase_) return;
  // Every keyframe that lists it, not only those it lists: an edge can be one-sided (a neighbour
  // counted it when they shared more points than they do now), and it is freed later.
  for (KeyFrame* kf : map_->keyframes())
    if (kf != this) kf->erase_connection(this);
  // Its points will no longer list it: they could be freed while these slots still named them.
  std::vector<MapPoint*> points(points_.size(), nullptr);
  points.swap(points_);
  for (MapPoint* mp : points)
    if (mp != nullptr) mp->erase_observation(this);
  connections_.clear();
  ordered_neighbours_.clear();
  ordered_weights_.clear();

  // Re-attach the children (ORB-SLAM2): repeatedly give the child with the strongest covisibility
  // to an already attached keyframe that keyframe as parent.
  std::set<KeyFrame*, ById> candidates;
  if (parent_ != nullptr) candidates.insert(parent_);
  while (!children_.empty()) {
    KeyFrame *best_child = nullptr, *best_parent = nullptr;
    int best_weight = -1;
    for (KeyFrame* child : children_) {
      if (child->is_bad()) continue;
      for (KeyFrame* cand : child->ordered_covisibles()) {
        if (candidates.count(cand) == 0) continue;
        const int w = child->weight(cand);
        if (w > best_weight) {
          best_weight = w;
          best_child = child;
          best_parent = cand;
        }
      }
    }
    if (best_child == nullptr) break;
    children_.erase(best_child);
    best_child->parent_ = best_parent;
    best_parent->children_.insert(best_child);
    candidates.insert(best_child);
  }
  for (KeyFrame* child : children_) {
    child->parent_ = parent_;
    if (parent_ != nullptr) parent_->children_.insert(child);
  }
  children_.clear();
  if (parent_ != nullptr) {
    parent_->children_.erase(this);
    T_c_parent_ = T_cw_ * parent_->T_wc();
  }
  // Frames tracked against this keyframe now follow its parent (Map::resolve_pose): so do its links,
  // their tracked odometry carried through this keyframe's pose against its parent.
  for (const auto& [id, T_this_other] : tracking_links_) {
    KeyFrame* other = map_->keyframe(id);
    if (other == nullptr) continue;
    other->tracking_links_.erase(id_);
    if (parent_ == nullptr || other == parent_) continue;
    const Eigen::Isometry3d T_parent_other = T_c_parent_.inverse() * T_this_other;
    parent_->tracking_links_.emplace(id, T_parent_other);
    other->tracking_links_.emplace(parent_->id_, T_parent_other.inverse());
  }
  tracking_links_.clear();
  bad_ = true;
  map_->erase_keyframe(this);
}

}  // namespace lrd::map
