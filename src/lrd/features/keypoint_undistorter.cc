#include "lrd/features/keypoint_undistorter.h"

#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <utility>

namespace lrd::features {

KeypointUndistorter::KeypointUndistorter(const camera::PinholeCamera& camera)
    : K_(camera.K_cv()), dist_(camera.distortion_cv()), identity_(camera.distortion.is_zero()) {
  const auto w = static_cast<float>(camera.width), h = static_cast<float>(camera.height);
  std::vector<cv::Point2f> corners{{0.0f, 0.0f}, {w, 0.0f}, {0.0f, h}, {w, h}};
  undistort_points(corners);
  const float x0 = std::min(corners[0].x, corners[2].x), x1 = std::max(corners[1].x, corners[3].x);
  const float y0 = std::min(corners[0].y, corners[1].y), y1 = std::max(corners[2].y, corners[3].y);
  bounds_ = cv::Rect2f(x0, y0, x1 - x0, y1 - y0);
}

void KeypointUndistorter::undistort_points(std::vector<cv::Point2f>& points) const {
  if (identity_ || points.empty()) return;
  // OpenCV's default stops after 5 fixed-point iterations, which leaves pixels of error in the
  // corners under strong radial distortion (TUM fr1); iterate until the reprojection of the
  // result is within 1e-4 px of the input instead.
  const cv::TermCriteria until(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-4);
  std::vector<cv::Point2f> ideal;
  cv::undistortPoints(points, ideal, K_, dist_, cv::noArray(), K_, until);
  points = std::move(ideal);
}

cv::Point2f KeypointUndistorter::undistort(const cv::Point2f& p) const {
  std::vector<cv::Point2f> points{p};
  undistort_points(points);
  return points[0];
}

std::vector<cv::KeyPoint> KeypointUndistorter::undistort(const std::vector<cv::KeyPoint>& keypoints) const {
  std::vector<cv::KeyPoint> out = keypoints;
  if (identity_) return out;
  std::vector<cv::Point2f> points(keypoints.size());
  for (std::size_t i = 0; i < keypoints.size(); ++i) points[i] = keypoints[i].pt;
  undistort_points(points);
  for (std::size_t i = 0; i < out.size(); ++i) out[i].pt = points[i];
  return out;
}

}  // namespace lrd::features
