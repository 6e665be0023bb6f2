#include "lrd/camera/pinhole_camera.h"

#include <string>
#include <string_view>
#include <vector>

#include "lrd/util/error.h"

namespace lrd::camera {

Eigen::Matrix3d PinholeCamera::K() const {
  Eigen::Matrix3d k;
  k << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0;
  return k;
}

cv::Mat PinholeCamera::K_cv() const {
  return (cv::Mat_<double>(3, 3) << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0);
}

cv::Mat PinholeCamera::distortion_cv() const {
  return (cv::Mat_<double>(1, 5) << distortion.k1, distortion.k2, distortion.p1, distortion.p2,
          distortion.k3);
}

namespace {

struct Preset {
  std::string_view name;
  double fx, fy, cx, cy;
  Distortion distortion;
  double depth_map_factor;
};

// Calibration published with the TUM RGB-D benchmark (freiburg1/2/3) and with Bonn RGB-D
// Dynamic (Palazzolo et al., IROS 2019: an ASUS Xtion, depth in units of 1/5000 m as in TUM);
// bf/ThDepth as in ORB-SLAM2's TUM1/2/3.yaml, which Bonn's
// Kinect-class sensor shares.
constexpr Preset kPresets[] = {
    {"tum1",
     517.306408,
     516.469215,
     318.643040,
     255.313989,
     {0.262383, -0.953104, -0.005358, 0.002628, 1.163314},
     5000.0},
    {"tum2",
     520.908620,
     521.007327,
     325.141442,
     249.701764,
     {0.231222, -0.784899, -0.003257, -0.000105, 0.917205},
     5208.0},
    {"tum3", 535.4, 539.2, 320.1, 247.6, {}, 5000.0},
    {"bonn",
     542.822841,
     542.576870,
     315.593520,
     237.756098,
     {0.039903, -0.099343, -0.000730, -0.000144, 0.0},
     5000.0},
};

}  // namespace

std::vector<std::string> camera_preset_names() {
  std::vector<std::string> names;
  for (const Preset& p : kPresets) names.emplace_back(p.name);
  return names;
}

PinholeCamera camera_preset(std::string_view name) {
  for (const Preset& p : kPresets) {
    if (p.name != name) continue;
    PinholeCamera cam;
    cam.name = std::string(name);
    cam.fx = p.fx;
    cam.fy = p.fy;
    cam.cx = p.cx;
    cam.cy = p.cy;
    cam.distortion = p.distortion;
    cam.depth_map_factor = p.depth_map_factor;
    cam.width = 640;
    cam.height = 480;
    cam.fps = 30.0;
    cam.bf = 40.0;
    cam.th_depth = 40.0;
    cam.rgb_order = true;
    return cam;
  }
  std::string valid;
  for (const Preset& p : kPresets) valid += (valid.empty() ? "" : ", ") + std::string(p.name);
  throw Error("unknown camera preset '" + std::string(name) + "' (valid: " + valid + ")");
}

}  // namespace lrd::camera
