#pragma once
// Rolling-shutter compensation (docs/slam-core.md, "Rolling shutter"). A rolling-shutter colour
// camera reads its rows out one after another over `readout_time`: a keypoint on row y was seen
// dt = readout_time * (y / (H - 1) - 1/2) away from the frame's stamp (the middle row). Tracking
// and mapping take every keypoint as seen at the stamp, so under a turning camera the frame is
// sheared (19 deg/s and a 28 ms readout: ~5 px between top and bottom rows) and the pose fitted to
// it, and the map points made from it, carry that shear. With the camera's velocity (the motion
// model's), each keypoint is moved to where it would have been seen at the stamp, as Kerl et al.
// (ICCV 2015) model the rows' poses, to first order: a constant velocity over one frame.
#include <Eigen/Geometry>

namespace lrd::data {
class Frame;
}

namespace lrd::tracking {

// `velocity`: T_c(k) c(k-1), the camera's motion over one frame period `frame_period` (s). The
// frame's camera gives the readout time (0: a global shutter, nothing is moved) and the height.
// Keypoints with depth move by the full motion and get the depth they had at the stamp; those
// without depth by the rotation alone (their translation's effect is unknown without depth).
void compensate_rolling_shutter(data::Frame& frame, const Eigen::Isometry3d& velocity, double frame_period);

}  // namespace lrd::tracking
