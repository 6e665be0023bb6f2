#include "lrd/dense/confirmation_mask.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace lrd::dense {

cv::Mat awaiting_confirmation(const cv::Mat& dynamic, cv::Size size, const DenseParams& params,
                              bool mask_carried) {
  if (mask_carried) return {size, CV_8U, cv::Scalar(255)};
  cv::Mat around = dynamic.empty() ? cv::Mat::zeros(size, CV_8U) : cv::Mat(dynamic != 0);
  if (const int r = params.mask_margin_px; r > 0)
    cv::dilate(around, around, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 2 * r + 1)));
  const int cols = std::min(params.edge_margin_px, size.width);
  around.colRange(0, cols).setTo(255);
  around.colRange(size.width - cols, size.width).setTo(255);
  return around;
}

}  // namespace lrd::dense
