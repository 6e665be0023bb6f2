#pragma once
// The view-frustum test (ORB-SLAM2's isInFrustum), one for the whole code base: where a map point
// appears in a view, if the view can see it at all.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

namespace lrd::data {
class Frame;
}
namespace lrd::map {
class MapPoint;
}

namespace lrd::match {

struct FrustumProjection {
  Eigen::Vector3d point_camera;  // the point in the view's camera frame
  Eigen::Vector2d pixel;         // its projection (undistorted pixels)
  float distance = 0.0f;         // from the camera centre
  float view_cos = 0.0f;         // cosine between the viewing ray and the point's mean normal
  int level = 0;                 // the pyramid level it should be found at
};

// Empty unless the point lies in front of the camera (pose T_cw of view `f`), projects inside the
// image, is within its scale-invariance distance range, and is seen at a viewing angle whose
// cosine is at least `min_view_cos` (0.5: 60 degrees).
[[nodiscard]] std::optional<FrustumProjection> project_in_frustum(const data::Frame& f,
                                                                  const Eigen::Isometry3d& T_cw,
                                                                  const map::MapPoint& mp,
                                                                  float min_view_cos = 0.5f);

// Projects `mp` into `f` at f's pose (viewing angle up to 60 degrees) and keeps the projection in
// mp.track, where OrbMatcher::search_by_projection reads it; returns track.in_view.
bool mark_for_projection_search(const data::Frame& f, map::MapPoint& mp);

}  // namespace lrd::match
