#pragma once
// sensor_msgs CameraInfo fields (the same in ROS 1 and ROS 2) to and from the camera lrd-slam
// works with.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/io/frame_source.h"

namespace lrd::bag {

// The calibration fields of a camera_info message.
struct CameraCalibration {
  std::uint32_t width = 0, height = 0;
  std::string distortion_model;
  std::vector<double> d;
  std::array<double, 9> k{}, r{};
  std::array<double, 12> p{};
};

// The intrinsics and distortion of a camera_info (plumb_bob or rational_polynomial: k1 k2 p1 p2
// k3). Throws lrd::Error for a zero size or an uncalibrated (all-zero) K.
[[nodiscard]] io::SourceCamera camera_from_calibration(const CameraCalibration& info);
// A plumb_bob camera_info of `camera` (R the identity, P = K with no baseline).
[[nodiscard]] CameraCalibration calibration_of(const camera::PinholeCamera& camera);

}  // namespace lrd::bag
