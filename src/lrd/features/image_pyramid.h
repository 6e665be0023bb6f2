#pragma once
// Scale pyramid of a grey image: level i is the image shrunk by scale_factor^i (ORB-SLAM2 and
// Rublee et al. 2011 detect ORB features on every level to gain scale invariance).
#include <opencv2/core.hpp>
#include <vector>

namespace lrd::features {

class ImagePyramid {
 public:
  // Throws lrd::Error for n_levels < 1 or scale_factor < 1 (scale 1 only with one level).
  ImagePyramid(int n_levels, float scale_factor);

  // Rebuilds every level from `grey` (CV_8UC1). Level 0 shares grey's pixels; the other levels
  // are kept between calls, so building pyramids of same-sized frames allocates nothing.
  void build(const cv::Mat& grey);
  // build() in steps, so that work on a level can start while the next ones are made:
  // set_base() sets level 0, build_level(i) makes level i from level i - 1 (1 <= i < levels()),
  // build_levels() makes levels 1.. in turn.
  void set_base(const cv::Mat& grey);
  void build_level(int i);
  void build_levels();

  [[nodiscard]] int levels() const { return static_cast<int>(scale_.size()); }
  [[nodiscard]] const cv::Mat& level(int i) const { return images_[i]; }
  // Nominal scale of each level (scale_factor^i) and its inverse.
  [[nodiscard]] const std::vector<float>& scale_factors() const { return scale_; }
  [[nodiscard]] const std::vector<float>& inv_scale_factors() const { return inv_scale_; }

  // Level pixel -> level-0 pixel. Pixel centres map through the exact ratio of the rounded image
  // sizes, which differs from scale_factor^i by up to half a pixel over the image.
  [[nodiscard]] cv::Point2f to_base(int level, float x, float y) const {
    return {(x + 0.5f) * ratio_[level].x - 0.5f, (y + 0.5f) * ratio_[level].y - 0.5f};
  }

 private:
  std::vector<float> scale_;
  std::vector<float> inv_scale_;
  std::vector<cv::Mat> images_;
  std::vector<cv::Point2f> ratio_;  // level-0 size / level size, per axis
};

}  // namespace lrd::features
