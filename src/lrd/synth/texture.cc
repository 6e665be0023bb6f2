#include "lrd/synth/texture.h"

#include <opencv2/imgproc.hpp>

#include "lrd/util/error.h"

namespace lrd::synth {

Texture::Texture(const cv::Mat& image) {
  if (image.empty() || image.type() != CV_8UC3) throw Error("texture: expected a non-empty 8-bit BGR image");
  auto pow2 = [](int n) {
    int p = 4;
    while (p * 2 <= n) p *= 2;
    return p;
  };
  cv::Mat base;
  cv::resize(image, base, cv::Size(pow2(image.cols), pow2(image.rows)), 0, 0, cv::INTER_AREA);
  mips_.push_back(base);
  while (mips_.back().cols > 4 && mips_.back().rows > 4) {
    cv::Mat down;
    cv::pyrDown(mips_.back(), down, cv::Size(mips_.back().cols / 2, mips_.back().rows / 2),
                cv::BORDER_REFLECT101);
    mips_.push_back(down);
  }
}

}  // namespace lrd::synth
