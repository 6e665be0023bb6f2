#include "lrd/tracking/rolling_shutter.h"

#include <vector>

#include "lrd/data/frame.h"
#include "lrd/geometry/se3.h"

namespace lrd::tracking {

void compensate_rolling_shutter(data::Frame& frame, const Eigen::Isometry3d& velocity, double frame_period) {
  const camera::PinholeCamera& cam = frame.camera();
  if (cam.readout_time <= 0.0 || frame_period <= 0.0 || cam.height < 2 || frame.size() == 0) return;
  // The camera's twist per second; over dt the camera moves by exp(dt * twist), taking a point
  // from camera coordinates at the stamp to those at the stamp + dt.
  const geometry::Vector6d twist = geometry::se3_log(velocity) / frame_period;
  std::vector<cv::Point2f> positions(frame.size());
  std::vector<float> depths(frame.size());
  for (std::size_t i = 0; i < frame.size(); ++i) {
    // The row as read out: the detected (distorted) pixel's.
    const double row = frame.keypoints()[i].pt.y;
    const double dt = cam.readout_time * (row / (cam.height - 1) - 0.5);
    const Eigen::Isometry3d stamp_from_row = geometry::se3_exp(dt * twist).inverse();
    const cv::Point2f& pt = frame.undistorted()[i].pt;
    const float depth = frame.depth(i);
    Eigen::Vector3d p = depth > 0.0f ? cam.unproject(pt.x, pt.y, depth) : cam.unproject(pt.x, pt.y, 1.0);
    p = depth > 0.0f ? Eigen::Vector3d(stamp_from_row * p) : Eigen::Vector3d(stamp_from_row.linear() * p);
    if (p.z() <= 0.0) {  // a motion this large is no constant-velocity frame: leave the keypoint
      positions[i] = pt;
      depths[i] = depth;
      continue;
    }
    const Eigen::Vector2d uv = cam.project(p);
    positions[i] = cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    depths[i] = depth > 0.0f ? static_cast<float>(p.z()) : depth;
  }
  frame.move_keypoints(positions, depths);
}

}  // namespace lrd::tracking
