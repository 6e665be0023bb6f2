#pragma once
// Intersection over union of two binary masks (non-zero pixels); two empty masks agree fully.
#include <opencv2/core.hpp>

namespace lrd::test {

inline double mask_iou(const cv::Mat& a, const cv::Mat& b) {
  const double inter = cv::countNonZero(a & b), uni = cv::countNonZero(a | b);
  return uni == 0 ? 1.0 : inter / uni;
}

}  // namespace lrd::test
