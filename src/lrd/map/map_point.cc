#include "lrd/map/map_point.h"

#include <algorithm>
#include <cmath>

#include "lrd/features/descriptor_distance.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"

namespace lrd::map {

MapPoint::MapPoint(std::uint64_t id, const Eigen::Vector3d& position, KeyFrame* reference,
                   std::uint64_t first_frame_id, Map* map)
    : id_(id),
      first_keyframe_id_(reference ? reference->id() : 0),
      first_frame_id_(first_frame_id),
      position_(position),
      reference_(reference),
      map_(map) {}

void MapPoint::restore_state(const SavedState& state) {
  first_keyframe_id_ = state.first_keyframe_id;
  normal_ = state.normal;
  descriptor_ = state.descriptor;
  min_distance_ = state.min_distance;
  max_distance_ = state.max_distance;
  visible_ = state.visible;
  found_ = state.found;
}

void MapPoint::add_observation(KeyFrame* kf, std::size_t index) {
  if (!observations_.emplace(kf, index).second) return;
  num_obs_ += kf->features().u_right(index) >= 0.0f ? 2 : 1;
}

void MapPoint::erase_observation(KeyFrame* kf) {
  const auto it = observations_.find(kf);
  if (it == observations_.end()) return;
  num_obs_ -= kf->features().u_right(it->second) >= 0.0f ? 2 : 1;
  observations_.erase(it);
  if (reference_ == kf) reference_ = observations_.empty() ? nullptr : observations_.begin()->first;
  if (num_obs_ <= 2) set_bad();
}

std::optional<std::size_t> MapPoint::index_in(KeyFrame* kf) const {
  const auto it = observations_.find(kf);
  if (it == observations_.end()) return std::nullopt;
  return it->second;
}

void MapPoint::set_bad() {
  if (bad_) return;
  bad_ = true;
  const Observations obs = std::move(observations_);
  observations_.clear();
  num_obs_ = 0;
  // Every slot: tracking may have matched the point to two keypoints of a keyframe.
  for (const auto& [kf, idx] : obs) kf->erase_map_point(this);
  map_->erase_map_point(this);
}

void MapPoint::replace(MapPoint* other) {
  if (other == this || other->id() == id_ || bad_) return;
  const Observations obs = std::move(observations_);
  observations_.clear();
  bad_ = true;
  replaced_by_ = other;
  for (const auto& [kf, idx] : obs) {
    if (!other->is_in_keyframe(kf)) {
      kf->add_map_point(other, idx);
      other->add_observation(kf, idx);
    } else {
      kf->erase_map_point(idx);
    }
    kf->erase_map_point(this);  // a second slot of the same keyframe
  }
  other->increase_found(found_);
  other->increase_visible(visible_);
  other->compute_distinctive_descriptor();
  map_->erase_map_point(this);
}

void MapPoint::compute_distinctive_descriptor() {
  if (bad_ || observations_.empty()) return;
  std::vector<const std::uint8_t*> descs;
  descs.reserve(observations_.size());
  for (const auto& [kf, idx] : observations_)
    if (!kf->is_bad()) descs.push_back(kf->features().descriptors().ptr(static_cast<int>(idx)));
  if (descs.empty()) return;
  const std::size_t n = descs.size();
  std::vector<int> dist(n * n, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      dist[i * n + j] = dist[j * n + i] = features::descriptor_distance(descs[i], descs[j]);
  // The medoid: least median distance to the other observations' descriptors.
  int best_median = INT32_MAX;
  std::size_t best = 0;
  std::vector<int> row(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::copy(dist.begin() + static_cast<long>(i * n), dist.begin() + static_cast<long>((i + 1) * n),
              row.begin());
    std::nth_element(row.begin(), row.begin() + static_cast<long>((n - 1) / 2), row.end());
    const int median = row[(n - 1) / 2];
    if (median < best_median) {
      best_median = median;
      best = i;
    }
  }
  descriptor_ = cv::Mat(1, 32, CV_8U);
  std::copy(descs[best], descs[best] + 32, descriptor_.ptr());
}

void MapPoint::update_normal_and_depth() {
  if (bad_ || observations_.empty() || reference_ == nullptr) return;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  int n = 0;
  for (const auto& [kf, idx] : observations_) {
    const Eigen::Vector3d d = position_ - kf->camera_center();
    const double norm = d.norm();
    if (norm > 0) normal += d / norm;
    ++n;
  }
  const auto ref = observations_.find(reference_);
  if (ref == observations_.end()) return;
  const data::Frame& f = reference_->features();
  const double dist = (position_ - reference_->camera_center()).norm();
  const int level = f.undistorted()[ref->second].octave;
  const float level_scale = f.scale_factors()[static_cast<std::size_t>(level)];
  max_distance_ = static_cast<float>(dist) * level_scale;
  min_distance_ = max_distance_ / f.scale_factors().back();
  normal_ = normal / static_cast<double>(n);
  const double nn = normal_.norm();
  if (nn > 0) normal_ /= nn;
}

int MapPoint::predict_scale(float distance, float log_scale_factor, int levels) const {
  const float ratio = max_distance_ / distance;
  int level = static_cast<int>(std::ceil(std::log(ratio) / log_scale_factor));
  return std::clamp(level, 0, levels - 1);
}

std::size_t MapPoint::memory_bytes() const {
  constexpr std::size_t kNode = 4 * sizeof(void*);  // a std::map node's links
  const std::size_t descriptor = descriptor_.empty() ? 0 : descriptor_.total() + sizeof(cv::UMatData);
  return sizeof(MapPoint) + descriptor + observations_.size() * (sizeof(Observations::value_type) + kNode);
}

}  // namespace lrd::map
