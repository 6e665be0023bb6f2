#include "lrd/synth/procedural_texture.h"

#include <opencv2/imgproc.hpp>

namespace lrd::synth::procedural {
namespace {

cv::RNG make_rng(std::uint64_t seed) {
  return cv::RNG(seed ^ 0x9E3779B97F4A7C15ull);
}

// Multi-octave tileable noise in [0,1].
cv::Mat fractal(int size, std::uint64_t seed) {
  cv::Mat acc = cv::Mat::zeros(size, size, CV_32F);
  float amp = 0.5f, total = 0.0f;
  for (int cell = size / 4, octave = 0; cell >= 2; cell /= 2, ++octave) {
    acc += amp * value_noise(size, cell, seed + static_cast<std::uint64_t>(octave) * 7919);
    total += amp;
    amp *= 0.6f;
  }
  return acc / total;
}

cv::Mat tint(const cv::Mat& gray01, const cv::Scalar& bgr, double contrast) {
  cv::Mat out(gray01.size(), CV_8UC3);
  for (int y = 0; y < gray01.rows; ++y) {
    for (int x = 0; x < gray01.cols; ++x) {
      const double g = 1.0 + contrast * (gray01.at<float>(y, x) - 0.5);
      cv::Vec3b& p = out.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) p[c] = cv::saturate_cast<uchar>(bgr[c] * g);
    }
  }
  return out;
}

void add_grain(cv::Mat& img, double sigma, std::uint64_t seed) {
  cv::RNG rng = make_rng(seed);
  cv::Mat noise(img.size(), CV_16SC3);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
  cv::Mat tmp;
  img.convertTo(tmp, CV_16SC3);
  tmp += noise;
  tmp.convertTo(img, CV_8UC3);
}

}  // namespace

cv::Mat value_noise(int size, int cell, std::uint64_t seed) {
  const int n = std::max(1, size / cell);
  cv::RNG rng = make_rng(seed);
  cv::Mat grid(n, n, CV_32F);
  rng.fill(grid, cv::RNG::UNIFORM, 0.0, 1.0);
  // Tile 3x3, upsample, crop the centre: smooth and seamless when repeated.
  cv::Mat tiled, up;
  cv::repeat(grid, 3, 3, tiled);
  cv::resize(tiled, up, cv::Size(3 * size, 3 * size), 0, 0, cv::INTER_CUBIC);
  return up(cv::Rect(size, size, size, size)).clone();
}

cv::Mat brick(int size, std::uint64_t seed) {
  cv::RNG rng = make_rng(seed);
  cv::Mat img(size, size, CV_8UC3, cv::Scalar(170, 175, 180));  // mortar
  const int rows = 8, cols = 4;
  const int bh = size / rows, bw = size / cols;
  const cv::Mat n = fractal(size, seed + 1);
  for (int r = 0; r < rows; ++r) {
    const int off = (r % 2) * bw / 2;
    for (int c = -1; c < cols; ++c) {
      const cv::Scalar col(40 + rng.uniform(0, 30), 60 + rng.uniform(0, 40), 120 + rng.uniform(0, 60));
      const int x0 = c * bw + off + 3, y0 = r * bh + 3;
      cv::rectangle(img, cv::Rect(x0, y0, bw - 6, bh - 6), col, cv::FILLED);
      if (x0 + bw > size) cv::rectangle(img, cv::Rect(x0 - size, y0, bw - 6, bh - 6), col, cv::FILLED);
    }
  }
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) img.at<cv::Vec3b>(y, x) *= 0.75 + 0.5 * n.at<float>(y, x);
  add_grain(img, 8.0, seed + 2);
  return img;
}

cv::Mat plaster(int size, const cv::Scalar& bgr, std::uint64_t seed) {
  cv::Mat img = tint(fractal(size, seed), bgr, 0.5);
  // Scattered darker flecks make plaster feature-bearing, as real walls are at close range.
  cv::RNG rng = make_rng(seed + 3);
  for (int i = 0; i < size * size / 400; ++i) {
    const cv::Point p(rng.uniform(0, size), rng.uniform(0, size));
    cv::circle(img, p, rng.uniform(1, 3), bgr * rng.uniform(0.55, 0.85), cv::FILLED, cv::LINE_AA);
  }
  add_grain(img, 4.0, seed + 4);
  return img;
}

cv::Mat carpet(int size, const cv::Scalar& bgr, std::uint64_t seed) {
  cv::Mat img = tint(fractal(size, seed), bgr, 0.8);
  add_grain(img, 14.0, seed + 5);
  return img;
}

cv::Mat plaid(int size, const cv::Scalar& a, const cv::Scalar& b, std::uint64_t seed) {
  cv::Mat img(size, size, CV_8UC3, a);
  cv::RNG rng = make_rng(seed);
  const int period = size / 8;
  for (int k = 0; k < 8; ++k) {
    const int w = period / 3 + rng.uniform(0, period / 4);
    cv::Mat roi_v = img(cv::Rect(k * period, 0, std::min(w, size - k * period), size));
    roi_v = 0.5 * roi_v + 0.5 * cv::Mat(roi_v.size(), CV_8UC3, b);
    cv::Mat roi_h = img(cv::Rect(0, k * period, size, std::min(w, size - k * period)));
    roi_h = 0.5 * roi_h + 0.5 * cv::Mat(roi_h.size(), CV_8UC3, b);
    cv::line(img, {k * period + w + 2, 0}, {k * period + w + 2, size}, cv::Scalar(240, 240, 240), 1);
    cv::line(img, {0, k * period + w + 2}, {size, k * period + w + 2}, cv::Scalar(240, 240, 240), 1);
  }
  add_grain(img, 10.0, seed + 6);
  return img;
}

cv::Mat stripes(int size, const cv::Scalar& a, const cv::Scalar& b, std::uint64_t seed) {
  cv::Mat img(size, size, CV_8UC3, a);
  cv::RNG rng = make_rng(seed);
  for (int y = 0; y < size;) {
    const int h = rng.uniform(size / 32, size / 10);
    cv::rectangle(img, cv::Rect(0, y, size, h / 2), b, cv::FILLED);
    y += h;
  }
  // A printed logo-like blob makes the shirt front distinctive.
  cv::circle(img, {size / 2, size / 2}, size / 8, cv::Scalar(30, 200, 230), cv::FILLED, cv::LINE_AA);
  cv::putText(img, "LRD", {size / 2 - size / 10, size / 2 + size / 40}, cv::FONT_HERSHEY_SIMPLEX,
              size / 300.0, cv::Scalar(20, 20, 20), std::max(1, size / 150), cv::LINE_AA);
  add_grain(img, 9.0, seed + 7);
  return img;
}

cv::Mat denim(int size, const cv::Scalar& bgr, std::uint64_t seed) {
  cv::Mat img = tint(fractal(size, seed), bgr, 0.6);
  for (int k = -size; k < size; k += 4) cv::line(img, {k, 0}, {k + size, size}, bgr * 0.8, 1);
  add_grain(img, 12.0, seed + 8);
  return img;
}

cv::Mat skin(int size, const cv::Scalar& bgr, std::uint64_t seed) {
  cv::Mat img = tint(fractal(size, seed), bgr, 0.25);
  add_grain(img, 3.0, seed + 9);
  return img;
}

cv::Mat hair(int size, const cv::Scalar& bgr, std::uint64_t seed) {
  cv::Mat img = tint(value_noise(size, 4, seed), bgr, 1.2);
  cv::RNG rng = make_rng(seed + 10);
  for (int i = 0; i < size; ++i) {
    const int x = rng.uniform(0, size);
    cv::line(img, {x, 0}, {x + rng.uniform(-size / 8, size / 8), size}, bgr * 1.6, 1, cv::LINE_AA);
  }
  return img;
}

cv::Mat book_spines(int size, std::uint64_t seed) {
  cv::RNG rng = make_rng(seed);
  cv::Mat img(size, size, CV_8UC3, cv::Scalar(30, 30, 30));
  for (int x = 0; x < size;) {
    const int w = rng.uniform(size / 40, size / 14);
    const cv::Scalar col(rng.uniform(20, 230), rng.uniform(20, 230), rng.uniform(20, 230));
    const int top = rng.uniform(0, size / 6);
    cv::rectangle(img, cv::Rect(x, top, w - 1, size - top), col, cv::FILLED);
    for (int t = 0; t < 3; ++t) {
      const int y = top + rng.uniform(size / 10, size - size / 10);
      cv::rectangle(img, cv::Rect(x + w / 4, y, std::max(1, w / 2), rng.uniform(4, size / 12)),
                    col * (rng.uniform(0, 2) ? 0.4 : 1.6), cv::FILLED);
    }
    x += w;
  }
  add_grain(img, 6.0, seed + 11);
  return img;
}

cv::Mat ceiling_tiles(int size, std::uint64_t seed) {
  cv::Mat img = tint(fractal(size, seed), cv::Scalar(215, 220, 222), 0.3);
  cv::RNG rng = make_rng(seed + 12);
  for (int i = 0; i < size * size / 150; ++i)
    cv::circle(img, {rng.uniform(0, size), rng.uniform(0, size)}, 1, cv::Scalar(150, 150, 155), cv::FILLED);
  cv::rectangle(img, cv::Rect(0, 0, size, size), cv::Scalar(160, 160, 165), 3);
  return img;
}

cv::Mat cardboard(int size, std::uint64_t seed) {
  cv::Mat img = tint(fractal(size, seed), cv::Scalar(90, 150, 190), 0.4);
  cv::rectangle(img, cv::Rect(size / 5, size / 3, size * 3 / 5, size / 3), cv::Scalar(40, 60, 80), 2);
  cv::putText(img, "FRAGILE", {size / 4, size / 2 + size / 30}, cv::FONT_HERSHEY_DUPLEX, size / 350.0,
              cv::Scalar(30, 30, 160), std::max(1, size / 200), cv::LINE_AA);
  cv::line(img, {0, size / 2}, {size, size / 2}, cv::Scalar(60, 110, 150), std::max(2, size / 40));
  add_grain(img, 6.0, seed + 13);
  return img;
}

}  // namespace lrd::synth::procedural
