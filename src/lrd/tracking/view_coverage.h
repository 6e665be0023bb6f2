#pragma once
// How much of the view a frame's tracked map points span: the keyframe-coverage rule
// (docs/slam-core.md). A map seen in one strip of the view leaves a rotation and a sideways
// translation nearly interchangeable, so tracking asks for a keyframe before that happens.
#include "lrd/data/frame.h"
#include "lrd/map/keyframe.h"

namespace lrd::tracking {

// The extent (5th to 95th percentile) of the tracked close keypoints (with a map point, not an
// outlier) against the extent of every close keypoint, across and down the image; the smaller of
// the two. 1 when fewer than 10 are tracked (nothing to judge). People in the middle of the view
// leave it whole; a map seen in one strip does not.
[[nodiscard]] double tracked_view_coverage(const data::Frame& frame);

// How many of `reference`'s map points (observed by at least min_observations keyframes) project
// inside the frame (at its pose) onto its dynamic mask, in front of the camera: hidden by people,
// not lost. 0 without a mask or a pose.
[[nodiscard]] int reference_points_hidden(const data::Frame& frame, const map::KeyFrame& reference,
                                          int min_observations);

}  // namespace lrd::tracking
