#pragma once
// Which of a keyframe's pixels the occupancy map takes as a surface only once a second keyframe
// confirms it (docs/occupancy.md): where a mask may have missed a person.
#include <opencv2/core.hpp>

#include "lrd/dense/dense_params.h"

namespace lrd::dense {

// 255 where the keyframe's own depth waits for confirmation, the dynamic pixels among them:
// within `params.mask_margin_px` of a dynamic pixel (where a mask misses a hand or a shoulder) or
// `params.edge_margin_px` of the image's left or right edge (people walk into and out of the view
// there, cut off, and a segmenter misses a cut-off body most: on walking_halfsphere FNet-lite left
// a walker's shoulder, 15-23 px wide at the right edge and far from any mask, unmasked; at the top
// and bottom edges, the floor and the walls' tops, the same wait cost walking_rpy 4 points of
// recall), or everywhere when the mask was carried from an earlier frame (it lags the people by
// their motion since). dynamic: CV_8UC1, nonzero = dynamic, or empty.
[[nodiscard]] cv::Mat awaiting_confirmation(const cv::Mat& dynamic, cv::Size size, const DenseParams& params,
                                            bool mask_carried);

}  // namespace lrd::dense
