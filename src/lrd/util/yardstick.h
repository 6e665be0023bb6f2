#pragma once
// The yardstick Y every benchmark and the HTML report measure time against: the median time of
// OpenCV's cv::ORB::create(1000, 1.2f, 8)->detectAndCompute on the same sequence's grey frames.
// These machines vary run to run, so targets are ratios to Y measured in the same run.
#include <algorithm>
#include <chrono>
#include <opencv2/features2d.hpp>
#include <vector>

namespace lrd::util {

inline double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Seconds of one detectAndCompute of `orb` (made as below) on `grey`: the yardstick per frame.
inline double yardstick_seconds(cv::Feature2D& orb, const cv::Mat& grey) {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  const auto start = std::chrono::steady_clock::now();
  orb.detectAndCompute(grey, cv::noArray(), keypoints, descriptors);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Median milliseconds of OpenCV ORB (1000 features, scale 1.2, 8 levels) over `grey` frames.
inline double yardstick_ms(const std::vector<cv::Mat>& grey) {
  auto orb = cv::ORB::create(1000, 1.2f, 8);
  std::vector<double> ms;
  for (const cv::Mat& g : grey) ms.push_back(1000.0 * yardstick_seconds(*orb, g));
  return median_of(ms);
}

}  // namespace lrd::util
