#include "lrd/mapping/keyframe_culling.h"

#include <cmath>

#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"

namespace lrd::mapping {

Redundancy redundancy(const map::KeyFrame& kf, int observers) {
  Redundancy r;
  const data::Frame& f = kf.features();
  const double close = f.camera().close_depth_threshold();
  const auto& points = kf.map_points();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const map::MapPoint* mp = points[i];
    if (mp == nullptr || mp->is_bad()) continue;
    if (f.depth(i) > close || f.depth(i) < 0.0f) continue;
    ++r.close_points;
    if (mp->num_observations() <= observers) continue;
    const int level = f.undistorted()[i].octave;
    int seen = 0;
    for (const auto& [other, index] : mp->observations()) {
      if (other == &kf) continue;
      if (other->features().undistorted()[index].octave <= level + 1 && ++seen >= observers) break;
    }
    if (seen >= observers) ++r.redundant;
  }
  return r;
}

const map::KeyFrame* older_keyframe_at_same_place(const map::KeyFrame& kf,
                                                  const KeyFrameCullingParams& params) {
  const double depth = kf.scene_depth_quantile(0.5);
  if (depth <= 0.0) return nullptr;
  const double max_baseline = params.place_baseline_ratio * depth;
  const double min_cos = std::cos(params.place_angle_deg * M_PI / 180.0);
  const Eigen::Vector3d centre = kf.camera_center();
  // The optical axis in the world: the third row of R_cw (orthonormal: linear(), not rotation(),
  // which would decompose the matrix for each keyframe compared).
  const Eigen::RowVector3d axis = kf.T_cw().linear().row(2);
  for (const map::KeyFrame* other : kf.ordered_covisibles()) {
    if (other->id() + static_cast<std::uint64_t>(params.place_keyframes_apart) > kf.id() || other->is_bad())
      continue;
    if ((other->camera_center() - centre).norm() > max_baseline) continue;
    if (other->T_cw().linear().row(2).dot(axis) < min_cos) continue;
    return other;
  }
  return nullptr;
}

CullingDecision judge_redundancy(const map::KeyFrame& kf, std::uint64_t newest_id,
                                 const KeyFrameCullingParams& params) {
  CullingDecision d;
  d.points = redundancy(kf, params.redundant_observers);
  const Redundancy& r = d.points;
  if (r.close_points == 0) return d;
  d.cull = r.redundant > params.redundant_ratio * r.close_points;
  if (d.cull || params.place_redundant_ratio <= 0.0 ||
      r.redundant <= params.place_redundant_ratio * r.close_points)
    return d;
  if (newest_id < kf.id() + static_cast<std::uint64_t>(params.place_keyframes_apart)) return d;
  d.same_place = older_keyframe_at_same_place(kf, params);
  d.cull = d.same_place != nullptr;
  return d;
}

}  // namespace lrd::mapping
