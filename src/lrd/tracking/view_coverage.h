#pragma once
// How much of the view a frame's tracked map points span: the keyframe-coverage rule
// (docs/slam-core.md). A map seen in one strip of the view leaves a rotation and a sideways
// translation nearly interchangeable, so tracking asks for a keyframe before that happens.
#include "lrd/data/frame.h"

namespace lrd::tracking {

// The extent (5th to 95th percentile) of the tracked close keypoints (with a map point, not an
// outlier) against the extent of every close keypoint, across and down the image; the smaller of
// the two. 1 when fewer than 10 are tracked (nothing to judge). People in the middle of the view
// leave it whole; a map seen in one strip does not.
[[nodiscard]] double tracked_view_coverage(const data::Frame& frame);

}  // namespace lrd::tracking
