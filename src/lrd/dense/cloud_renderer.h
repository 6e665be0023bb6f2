#pragma once
// A picture of the dense map from a virtual camera (like the paper's Fig. 18): points projected
// with a z-buffer, each drawn as a small square so the surfaces close up.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/dense/point_cloud.h"

namespace lrd::dense {

// Renders `cloud` seen by `camera` at camera-to-world pose T_wc (BGR, background dark grey).
[[nodiscard]] cv::Mat render_cloud(const PointCloud& cloud, const camera::PinholeCamera& camera,
                                   const Eigen::Isometry3d& T_wc, int point_px = 2);

// A viewpoint that shows the whole map: `back` metres behind and `up` metres above the camera
// pose `reference` (camera-to-world; the first keyframe's), looking at the centroid of the cloud.
[[nodiscard]] Eigen::Isometry3d overview_pose(const PointCloud& cloud, const Eigen::Isometry3d& reference,
                                              double back = 1.5, double up = 1.0);

}  // namespace lrd::dense
