#pragma once
// Carries an older frame's dynamic mask to the current frame (async segmentation): each masked
// pixel with depth moves with the camera's motion between the two frames (predicted by the
// motion model), pixels without depth stay where they were, and the result is dilated by the
// motion the rigid prediction cannot know (people move on their own): the older, the wider.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "lrd/camera/pinhole_camera.h"

namespace lrd::dynamic {

// `mask` CV_8UC1 (nonzero = dynamic) and `depth` CV_32FC1 metres of frame k; `T_t_k` maps frame
// k's camera coordinates to frame t's. Returns frame t's mask (255 = dynamic), not dilated.
[[nodiscard]] cv::Mat propagate_mask(const cv::Mat& mask, const cv::Mat& depth,
                                     const Eigen::Isometry3d& T_t_k, const camera::PinholeCamera& camera);

// Grows nonzero pixels by a disc of `radius` pixels (in place, set pixels become 255; radius 0:
// unchanged).
void dilate_mask(cv::Mat& mask, int radius);
// The same into a new mask (`mask` untouched; radius 0: a copy): no copy back into the caller's buffer.
[[nodiscard]] cv::Mat dilated_mask(const cv::Mat& mask, int radius);

// From this radius on, carry_mask works at half resolution.
inline constexpr int kHalfResolutionRadius = 9;

// propagate_mask, then dilate_mask by `radius`, as one step: below kHalfResolutionRadius exactly
// that; from it on at half resolution (2x2 blocks move as one), which covers the exact result and
// may overshoot its edge by a few pixels (at most 7 in tests/unit/test_mask_carry.cc). A new mask;
// `mask` is left as it is.
[[nodiscard]] cv::Mat carry_mask(const cv::Mat& mask, const cv::Mat& depth, const Eigen::Isometry3d& T_t_k,
                                 const camera::PinholeCamera& camera, int radius);

}  // namespace lrd::dynamic
