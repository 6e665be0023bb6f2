// camera::ImageUndistorter: a distorted image resampled to the ideal pinhole, as the dense stage
// needs it (each ideal pixel holds what the lens put at its distorted position).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "lrd/camera/image_undistorter.h"
#include "lrd/util/error.h"

namespace {

using lrd::camera::PinholeCamera;

// TUM freiburg2's lens (as the `tum` realism profile renders it).
PinholeCamera fr2_lens() {
  PinholeCamera cam;
  cam.distortion = {0.2312, -0.7849, -0.0033, -0.0001, 0.9172};
  return cam;
}

// Brown-Conrady, OpenCV's order: the raw pixel of an ideal one.
cv::Point2d distort(const PinholeCamera& cam, double u, double v) {
  const auto& d = cam.distortion;
  const double x = (u - cam.cx) / cam.fx, y = (v - cam.cy) / cam.fy, r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  const double xd = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
  const double yd = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
  return {cam.fx * xd + cam.cx, cam.fy * yd + cam.cy};
}

// Each raw pixel holds its own coordinates.
cv::Mat coordinates(const PinholeCamera& cam) {
  cv::Mat raw(cam.height, cam.width, CV_32FC2);
  for (int v = 0; v < raw.rows; ++v)
    for (int u = 0; u < raw.cols; ++u)
      raw.at<cv::Vec2f>(v, u) = {static_cast<float>(u), static_cast<float>(v)};
  return raw;
}

TEST(ImageUndistorter, EachIdealPixelHoldsItsDistortedPositionsValue) {
  const PinholeCamera cam = fr2_lens();
  const lrd::camera::ImageUndistorter undistorter(cam);
  ASSERT_TRUE(undistorter.active());
  const cv::Mat raw = coordinates(cam);
  const cv::Mat smooth = undistorter.smooth(raw), nearest = undistorter.nearest(raw);
  double largest_shift = 0.0;
  for (int v = 40; v < cam.height - 40; v += 37)
    for (int u = 40; u < cam.width - 40; u += 41) {
      const cv::Point2d d = distort(cam, u, v);
      const cv::Vec2f s = smooth.at<cv::Vec2f>(v, u), n = nearest.at<cv::Vec2f>(v, u);
      EXPECT_NEAR(s[0], d.x, 0.05) << u << "," << v;
      EXPECT_NEAR(s[1], d.y, 0.05) << u << "," << v;
      // Nearest: a raw pixel's own value, within half a pixel of the position.
      EXPECT_EQ(n[0], std::round(n[0]));
      EXPECT_LE(std::abs(n[0] - d.x), 0.51) << u << "," << v;
      EXPECT_LE(std::abs(n[1] - d.y), 0.51) << u << "," << v;
      largest_shift = std::max(largest_shift, std::hypot(d.x - u, d.y - v));
    }
  EXPECT_GT(largest_shift, 5.0);  // the lens moves the border by pixels: worth resampling
}

TEST(ImageUndistorter, WithoutDistortionNothingIsResampled) {
  const PinholeCamera pinhole;
  const lrd::camera::ImageUndistorter undistorter(pinhole);
  EXPECT_FALSE(undistorter.active());
  const cv::Mat raw = coordinates(pinhole);
  EXPECT_EQ(undistorter.smooth(raw).data, raw.data);
  EXPECT_EQ(undistorter.nearest(raw).data, raw.data);
}

TEST(ImageUndistorter, AnImageOfAnotherSizeIsAnError) {
  const lrd::camera::ImageUndistorter undistorter(fr2_lens());
  EXPECT_THROW((void)undistorter.nearest(cv::Mat::zeros(240, 320, CV_32F)), lrd::Error);
  EXPECT_TRUE(undistorter.nearest(cv::Mat()).empty());
}

}  // namespace
