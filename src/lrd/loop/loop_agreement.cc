#include "lrd/loop/loop_agreement.h"

#include <algorithm>
#include <set>

#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"

namespace lrd::loop {

namespace {
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}
}  // namespace

LoopAgreement measure_loop_agreement(const std::vector<map::KeyFrame*>& neighbourhood,
                                     const map::KeyFrame& loop_keyframe, const Eigen::Isometry3d& motion) {
  const data::Frame& f = loop_keyframe.features();
  const camera::PinholeCamera& cam = f.camera();
  const Eigen::Isometry3d& T_cw = loop_keyframe.T_cw();
  std::set<const map::MapPoint*, map::ById> seen;
  std::vector<double> before, after;
  for (const map::KeyFrame* kf : neighbourhood) {
    for (const map::MapPoint* mp : kf->map_points()) {
      if (mp == nullptr || mp->is_bad() || !seen.insert(mp).second) continue;
      const auto& obs = mp->observations();
      const auto it =
          std::find_if(obs.begin(), obs.end(), [&](const auto& o) { return o.first == &loop_keyframe; });
      if (it == obs.end()) continue;
      const cv::KeyPoint& kp = f.undistorted()[it->second];
      const Eigen::Vector2d measured(kp.pt.x, kp.pt.y);
      const Eigen::Vector3d now = T_cw * mp->position(), moved = T_cw * (motion * mp->position());
      // Behind the camera after the move: as far off as a point can be.
      before.push_back(now.z() > 0.0 ? (cam.project(now) - measured).norm() : 1e6);
      after.push_back(moved.z() > 0.0 ? (cam.project(moved) - measured).norm() : 1e6);
    }
  }
  return {before.size(), median(std::move(before)), median(std::move(after))};
}

}  // namespace lrd::loop
