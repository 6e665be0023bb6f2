#include "lrd/bag/camera_info.h"

#include <fmt/format.h>

#include "lrd/util/error.h"

namespace lrd::bag {

io::SourceCamera camera_from_calibration(const CameraCalibration& info) {
  if (info.width == 0 || info.height == 0)
    throw lrd::Error(fmt::format("camera_info has a zero size ({}x{})", info.width, info.height));
  if (!(info.k[0] > 0.0) || !(info.k[4] > 0.0))
    throw lrd::Error("camera_info is uncalibrated (K has no positive focal lengths)");
  io::SourceCamera c;
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.fx = info.k[0];
  c.fy = info.k[4];
  c.cx = info.k[2];
  c.cy = info.k[5];
  if (!info.d.empty() && info.distortion_model != "plumb_bob" &&
      info.distortion_model != "rational_polynomial")
    throw lrd::Error("camera_info distortion model '" + info.distortion_model +
                     "' is not supported (plumb_bob, rational_polynomial)");
  const auto d = [&info](std::size_t i) { return i < info.d.size() ? info.d[i] : 0.0; };
  c.k1 = d(0);
  c.k2 = d(1);
  c.p1 = d(2);
  c.p2 = d(3);
  c.k3 = d(4);
  return c;
}

CameraCalibration calibration_of(const camera::PinholeCamera& camera) {
  CameraCalibration info;
  info.width = static_cast<std::uint32_t>(camera.width);
  info.height = static_cast<std::uint32_t>(camera.height);
  info.distortion_model = "plumb_bob";
  const camera::Distortion& d = camera.distortion;
  info.d = {d.k1, d.k2, d.p1, d.p2, d.k3};
  info.k = {camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0};
  info.r = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.p = {camera.fx, 0.0, camera.cx, 0.0, 0.0, camera.fy, camera.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  return info;
}

}  // namespace lrd::bag
