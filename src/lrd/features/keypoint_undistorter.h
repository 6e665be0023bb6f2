#pragma once
// Moves keypoints from the distorted image to the ideal pinhole image of the same camera
// (ORB-SLAM2's Frame::UndistortKeyPoints), so the geometry downstream needs no distortion model.
#include <opencv2/core.hpp>
#include <vector>

#include "lrd/camera/pinhole_camera.h"

namespace lrd::features {

class KeypointUndistorter {
 public:
  explicit KeypointUndistorter(const camera::PinholeCamera& camera);

  // True when the camera has no distortion: undistort() then copies its input.
  [[nodiscard]] bool is_identity() const { return identity_; }
  // The same keypoints (octave, angle, size, response kept) at their undistorted positions.
  [[nodiscard]] std::vector<cv::KeyPoint> undistort(const std::vector<cv::KeyPoint>& keypoints) const;
  [[nodiscard]] cv::Point2f undistort(const cv::Point2f& p) const;
  // Bounds of the undistorted image: the box around the undistorted image corners (ORB-SLAM2's
  // ComputeImageBounds), for assigning keypoints to a grid.
  [[nodiscard]] cv::Rect2f undistorted_bounds() const { return bounds_; }

 private:
  void undistort_points(std::vector<cv::Point2f>& points) const;

  cv::Mat K_, dist_;
  bool identity_;
  cv::Rect2f bounds_;
};

}  // namespace lrd::features
