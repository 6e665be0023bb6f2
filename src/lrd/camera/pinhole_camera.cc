#include "lrd/camera/pinhole_camera.h"

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

std::vector<std::string> camera_preset_names() {
  return {"tum1", "tum2", "tum3", "bonn"};
}

PinholeCamera camera_preset(std::string_view name) {
  // Calibration published with the TUM RGB-D benchmark (freiburg1/2/3) and with Bonn RGB-D
  // Dynamic (Palazzolo et al., IROS 2019: an ASUS Xtion, depth in units of 1/5000 m as in TUM);
  // bf/ThDepth as in ORB-SLAM2's TUM1/2/3.yaml, which Bonn's Kinect-class sensor shares.
  PinholeCamera cam;
  cam.name = std::string(name);
  if (name == "tum1") {
    cam.fx = 517.306408;
    cam.fy = 516.469215;
    cam.cx = 318.643040;
    cam.cy = 255.313989;
    cam.distortion = {0.262383, -0.953104, -0.005358, 0.002628, 1.163314};
    cam.depth_map_factor = 5000.0;
  } else if (name == "tum2") {
    cam.fx = 520.908620;
    cam.fy = 521.007327;
    cam.cx = 325.141442;
    cam.cy = 249.701764;
    cam.distortion = {0.231222, -0.784899, -0.003257, -0.000105, 0.917205};
    cam.depth_map_factor = 5208.0;
  } else if (name == "tum3") {
    cam.fx = 535.4;
    cam.fy = 539.2;
    cam.cx = 320.1;
    cam.cy = 247.6;
    cam.distortion = {};
    cam.depth_map_factor = 5000.0;
  } else if (name == "bonn") {
    cam.fx = 542.822841;
    cam.fy = 542.576870;
    cam.cx = 315.593520;
    cam.cy = 237.756098;
    cam.distortion = {0.039903, -0.099343, -0.000730, -0.000144, 0.0};
    cam.depth_map_factor = 5000.0;
  } else {
    throw Error("unknown camera preset '" + std::string(name) + "' (valid: tum1, tum2, tum3, bonn)");
  }
  cam.width = 640;
  cam.height = 480;
  cam.fps = 30.0;
  cam.bf = 40.0;
  cam.th_depth = 40.0;
  cam.rgb_order = true;
  return cam;
}

}  // namespace lrd::camera
