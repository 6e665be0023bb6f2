#include "lrd/match/frustum.h"

#include <cmath>

#include "lrd/data/frame.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"

namespace lrd::match {

std::optional<FrustumProjection> project_in_frustum(const data::Frame& f, const Eigen::Isometry3d& T_cw,
                                                    const map::MapPoint& mp, float min_view_cos) {
  FrustumProjection p;
  p.point_camera = T_cw * mp.position();
  if (p.point_camera.z() <= 0.0) return std::nullopt;
  p.pixel = f.camera().project(p.point_camera);
  if (!f.in_bounds(p.pixel.x(), p.pixel.y())) return std::nullopt;
  const Eigen::Vector3d po = mp.position() - T_cw.inverse().translation();
  p.distance = static_cast<float>(po.norm());
  if (p.distance < mp.min_distance_invariance() || p.distance > mp.max_distance_invariance())
    return std::nullopt;
  const double dot = po.dot(mp.normal());
  if (dot < static_cast<double>(min_view_cos) * p.distance) return std::nullopt;
  p.view_cos = static_cast<float>(dot / p.distance);
  const auto& sf = f.scale_factors();
  p.level = mp.predict_scale(p.distance, sf.size() > 1 ? std::log(sf[1]) : 1.0f, static_cast<int>(sf.size()));
  return p;
}

bool mark_for_projection_search(const data::Frame& f, map::MapPoint& mp) {
  const auto seen = project_in_frustum(f, f.T_cw(), mp, 0.5f);
  mp.track.in_view = seen.has_value();
  if (!seen) return false;
  mp.track.proj_x = static_cast<float>(seen->pixel.x());
  mp.track.proj_y = static_cast<float>(seen->pixel.y());
  mp.track.proj_xr = static_cast<float>(seen->pixel.x() - f.camera().bf / seen->point_camera.z());
  mp.track.scale_level = seen->level;
  mp.track.view_cos = seen->view_cos;
  return true;
}

}  // namespace lrd::match
