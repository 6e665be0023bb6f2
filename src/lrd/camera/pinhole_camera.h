#pragma once
// RGB-D pinhole camera with Brown-Conrady distortion (OpenCV's k1 k2 p1 p2 k3), as in the
// ORB-SLAM2 settings files. Camera frame: x right, y down, z forward (OpenCV).
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace lrd::camera {

struct Distortion {
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;
  [[nodiscard]] bool is_zero() const { return k1 == 0.0 && k2 == 0.0 && p1 == 0.0 && p2 == 0.0 && k3 == 0.0; }
};

struct PinholeCamera {
  std::string name = "custom";
  int width = 640;
  int height = 480;
  double fx = 535.4, fy = 539.2, cx = 320.1, cy = 247.6;
  Distortion distortion;
  double fps = 30.0;
  // Stereo baseline times fx ("Camera.bf"); RGB-D uses it for the virtual right coordinate.
  double bf = 40.0;
  // Close/far split in baselines ("ThDepth"): depth < th_depth * bf / fx counts as close.
  double th_depth = 40.0;
  // 16-bit depth PNG value per metre ("DepthMapFactor").
  double depth_map_factor = 5000.0;
  // Colour order of the input images (Camera.RGB: 1 = RGB, 0 = BGR).
  bool rgb_order = true;
  // Noise of the depth sensor's disparity bf / z (px) for a keypoint of the finest pyramid level,
  // whose position noise is 1 px; both scale with the level. ORB-SLAM2 treats depth as a stereo
  // match as noisy as the keypoint (1.0); a structured-light sensor resolves 1/8 px of disparity
  // (Khoshelham & Elberink 2012), and at 1.0 bundle adjustment slides points along their rays by
  // centimetres to absorb sub-pixel keypoint noise (docs/slam-core.md, "Depth weight").
  double disparity_sigma = 0.125;
  // Rolling shutter: the colour image's rows are read out top to bottom over this time (s),
  // centred on the frame's stamp ("Camera.readoutTime"; 0: a global shutter). Tracking moves each
  // keypoint to the stamp by the camera's velocity (tracking/rolling_shutter.h).
  double readout_time = 0.0;

  // chi2 of an RGB-D observation of the camera-frame point p_c (z > 0): the keypoint (u, v) and,
  // with depth (u_right >= 0), the measured disparity u - u_right, each whitened by its sigma;
  // inv_sigma2 is the keypoint level's 1 / sigma^2. Compare with 7.815 (3 dof) or 5.991 (2 dof).
  [[nodiscard]] double reprojection_chi2(const Eigen::Vector3d& p_c, double u, double v, double u_right,
                                         double inv_sigma2) const {
    const double iz = 1.0 / p_c.z();
    const double eu = u - (fx * p_c.x() * iz + cx), ev = v - (fy * p_c.y() * iz + cy);
    double e2 = eu * eu + ev * ev;
    if (u_right >= 0.0) {
      const double ed = (u - u_right) - bf * iz;
      e2 += ed * ed / (disparity_sigma * disparity_sigma);
    }
    return e2 * inv_sigma2;
  }

  [[nodiscard]] Eigen::Matrix3d K() const;
  [[nodiscard]] cv::Mat K_cv() const;           // 3x3 CV_64F
  [[nodiscard]] cv::Mat distortion_cv() const;  // 1x5 CV_64F, OpenCV order k1 k2 p1 p2 k3
  [[nodiscard]] double baseline() const { return bf / fx; }
  [[nodiscard]] double close_depth_threshold() const { return th_depth * baseline(); }

  // Ideal (undistorted) projection of a point in the camera frame; z must be > 0.
  [[nodiscard]] Eigen::Vector2d project(const Eigen::Vector3d& p_c) const {
    return {fx * p_c.x() / p_c.z() + cx, fy * p_c.y() / p_c.z() + cy};
  }
  // Back-projection of an undistorted pixel at depth z.
  [[nodiscard]] Eigen::Vector3d unproject(double u, double v, double z) const {
    return {(u - cx) * z / fx, (v - cy) * z / fy, z};
  }
};

// Built-in presets with a dataset's published calibration: "tum1", "tum2", "tum3" (TUM RGB-D's
// freiburg1/2/3) and "bonn" (Bonn RGB-D Dynamic).
// Throws lrd::Error naming the valid presets for any other name.
[[nodiscard]] PinholeCamera camera_preset(std::string_view name);
[[nodiscard]] std::vector<std::string> camera_preset_names();

}  // namespace lrd::camera
