#include "lrd/features/image_pyramid.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

#include "lrd/util/error.h"

namespace lrd::features {

ImagePyramid::ImagePyramid(int n_levels, float scale_factor) {
  if (n_levels < 1) throw Error("ORB pyramid: n_levels must be >= 1, got " + std::to_string(n_levels));
  if (!(scale_factor >= 1.0f) || (scale_factor == 1.0f && n_levels > 1)) {
    throw Error("ORB pyramid: scale_factor must be > 1, got " + std::to_string(scale_factor));
  }
  scale_.resize(n_levels);
  inv_scale_.resize(n_levels);
  double s = 1.0;
  for (int i = 0; i < n_levels; ++i, s *= scale_factor) {
    scale_[i] = static_cast<float>(s);
    inv_scale_[i] = static_cast<float>(1.0 / s);
  }
  images_.resize(n_levels);
  ratio_.assign(n_levels, cv::Point2f(1.0f, 1.0f));
}

void ImagePyramid::build(const cv::Mat& grey) {
  set_base(grey);
  build_levels();
}

void ImagePyramid::set_base(const cv::Mat& grey) {
  CV_Assert(grey.type() == CV_8UC1 && !grey.empty());
  images_[0] = grey;
}

void ImagePyramid::build_levels() {
  for (int i = 1; i < levels(); ++i) build_level(i);
}

void ImagePyramid::build_level(int i) {
  CV_Assert(i >= 1 && i < levels());
  const cv::Mat& grey = images_[0];
  // Sizes round from level 0, as ORB-SLAM2 does; each level shrinks the previous one, which is
  // cheaper and smoother than shrinking level 0 by a large factor with bilinear sampling.
  const cv::Size size(std::max(1, static_cast<int>(std::lround(grey.cols * inv_scale_[i]))),
                      std::max(1, static_cast<int>(std::lround(grey.rows * inv_scale_[i]))));
  cv::resize(images_[i - 1], images_[i], size, 0.0, 0.0, cv::INTER_LINEAR);
  ratio_[i] = {static_cast<float>(grey.cols) / static_cast<float>(size.width),
               static_cast<float>(grey.rows) / static_cast<float>(size.height)};
}

}  // namespace lrd::features
