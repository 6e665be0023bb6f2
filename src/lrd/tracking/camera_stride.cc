#include "lrd/tracking/camera_stride.h"

#include "lrd/map/map.h"

namespace lrd::tracking {

std::optional<CameraStride> recent_stride(const std::vector<FrameRecord>& records, const map::Map& map,
                                          double timestamp, const Eigen::Vector3d& t_wc, double window,
                                          double min_seconds) {
  const FrameRecord* oldest = nullptr;
  for (auto it = records.rbegin(); it != records.rend(); ++it) {
    if (it->state != TrackingState::Ok || !it->reference) break;
    if (timestamp - it->timestamp > window) break;
    oldest = &*it;
  }
  if (oldest == nullptr || timestamp - oldest->timestamp < min_seconds) return std::nullopt;
  const Eigen::Vector3d from = map.resolve_pose(*oldest->reference, oldest->T_c_ref).inverse().translation();
  return CameraStride{(t_wc - from).norm(), timestamp - oldest->timestamp, oldest, from};
}

}  // namespace lrd::tracking
