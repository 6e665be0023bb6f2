#include "lrd/tracking/camera_stride.h"

#include "lrd/map/map.h"

namespace lrd::tracking {

Eigen::Vector3d recorded_centre(const FrameRecord& record, const map::Map& map) {
  return map.resolve_pose(*record.reference, record.T_c_ref).inverse().translation();
}

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
  const Eigen::Vector3d from = recorded_centre(*oldest, map);
  return CameraStride{(t_wc - from).norm(), timestamp - oldest->timestamp, oldest, from};
}

}  // namespace lrd::tracking
