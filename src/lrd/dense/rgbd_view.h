#pragma once
// One posed RGB-D image as the dense stage sees it: a keyframe's colour, depth and dynamic mask.
#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/core.hpp>

namespace lrd::dense {

struct RgbdView {
  cv::Mat bgr;      // CV_8UC3
  cv::Mat depth;    // CV_32FC1 metres, 0 = no measurement
  cv::Mat dynamic;  // CV_8UC1, nonzero = dynamic (empty: nothing dynamic)
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();  // world-to-camera
};

// True when the depth at (u, v) differs from a 4-neighbour's by more than `ratio` x z, i.e. the
// pixel may mix foreground and background (flying pixels at outlines).
[[nodiscard]] inline bool on_depth_edge(const cv::Mat& depth, int u, int v, double ratio) {
  const float z = depth.at<float>(v, u);
  const float limit = static_cast<float>(ratio) * z;
  const auto jumps = [&](int uu, int vv) {
    if (uu < 0 || vv < 0 || uu >= depth.cols || vv >= depth.rows) return false;
    const float n = depth.at<float>(vv, uu);
    return !(n > 0.0f) || std::abs(n - z) > limit;  // no measurement (0 or NaN) next to it: an edge
  };
  return jumps(u - 1, v) || jumps(u + 1, v) || jumps(u, v - 1) || jumps(u, v + 1);
}

}  // namespace lrd::dense
