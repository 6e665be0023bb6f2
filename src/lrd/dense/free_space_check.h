#pragma once
// Free-space check of keyframe clouds: a point another keyframe sees *through* — its depth image
// shows a surface clearly behind the point, on a pixel that is not dynamic there — was not there
// when that keyframe looked: a person the mask missed, or a flying pixel. Each such view is a
// vote; points with enough votes stay out of the map. Masks from a network miss a person's
// outline and limbs now and then; this is what keeps those pixels from becoming ghosts.
#include <cstdint>
#include <vector>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/dense/point_cloud.h"
#include "lrd/dense/rgbd_view.h"

namespace lrd::dense {

struct FreeSpaceParams {
  // How many of the latest keyframes each new keyframe is checked against, both ways. A window
  // of 10 keyframes spans about 2 s when the camera rolls (walking_rpy: a keyframe every 6
  // frames), too short for a person standing in view to leave it: 1.85 % ghosts with 20, 0.18 %
  // with 40 (docs/dense-map.md).
  int keyframes = 40;
  int step = 2;          // every step-th of them: the same span of time for half the work
  int votes = 1;         // views that must see through a point to drop it (0: no check)
  double margin = 0.05;  // m; plus margin_ratio x z: how far behind the point the view's surface must be
  double margin_ratio = 0.05;
};

// The view at 1/factor resolution for the check: per block the nearest valid depth (a point is
// voted against only if even the nearest surface there is behind it) and "dynamic" if any pixel
// is. 16 times less memory to sweep per view at factor 4, so the dense thread keeps out of the
// caches the tracking thread works in; `camera` scaled to match.
[[nodiscard]] RgbdView coarse_view(const RgbdView& view, int factor);
[[nodiscard]] camera::PinholeCamera coarse_camera(const camera::PinholeCamera& camera, int factor);

// Adds one vote to votes[i] for each point of `cloud` (in the camera frame of pose `T_cw_cloud`)
// that `view` sees through. `votes` has the cloud's size.
void vote_free_space(const PointCloud& cloud, const Eigen::Isometry3d& T_cw_cloud, const RgbdView& view,
                     const camera::PinholeCamera& camera, const FreeSpaceParams& params,
                     std::vector<std::uint8_t>& votes);

}  // namespace lrd::dense
