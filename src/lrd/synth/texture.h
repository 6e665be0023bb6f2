#pragma once
// A mip-mapped RGB texture with wrap-around bilinear sampling, for the synthetic renderer.
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace lrd::synth {

class Texture {
 public:
  Texture() = default;
  // `image` is CV_8UC3 (BGR), resized to power-of-two sides (for cheap wrapping); the mip chain
  // is built by repeated pyrDown down to 4x4.
  explicit Texture(const cv::Mat& image);

  [[nodiscard]] int levels() const { return static_cast<int>(mips_.size()); }
  [[nodiscard]] int width() const { return mips_.empty() ? 0 : mips_[0].cols; }
  [[nodiscard]] int height() const { return mips_.empty() ? 0 : mips_[0].rows; }
  [[nodiscard]] const cv::Mat& level(int l) const { return mips_[static_cast<std::size_t>(l)]; }

  // Bilinear sample at texture coordinates (u, v) in repeat units (1.0 = one tile), at mip level
  // `l`; writes B, G, R as floats in [0, 255].
  void sample(int l, float u, float v, float out[3]) const {
    const cv::Mat& m = mips_[static_cast<std::size_t>(l)];
    const float x = u * static_cast<float>(m.cols) - 0.5f;
    const float y = v * static_cast<float>(m.rows) - 0.5f;
    const int ix = fast_floor(x), iy = fast_floor(y);
    const float ax = x - static_cast<float>(ix), ay = y - static_cast<float>(iy);
    // Sizes are powers of two, so wrapping is a mask.
    const int mx = m.cols - 1, my = m.rows - 1;
    const int x0 = ix & mx, y0 = iy & my, x1 = (ix + 1) & mx, y1 = (iy + 1) & my;
    const std::uint8_t* r0 = m.ptr<std::uint8_t>(y0);
    const std::uint8_t* r1 = m.ptr<std::uint8_t>(y1);
    const float w00 = (1 - ax) * (1 - ay), w10 = ax * (1 - ay), w01 = (1 - ax) * ay, w11 = ax * ay;
    for (int c = 0; c < 3; ++c) {
      out[c] = w00 * r0[3 * x0 + c] + w10 * r0[3 * x1 + c] + w01 * r1[3 * x0 + c] + w11 * r1[3 * x1 + c];
    }
  }

 private:
  static int fast_floor(float x) {
    const int i = static_cast<int>(x);
    return x < static_cast<float>(i) ? i - 1 : i;
  }
  std::vector<cv::Mat> mips_;
};

}  // namespace lrd::synth
