#include "lrd/data/rgbd_input.h"

#include <fmt/format.h>

#include <opencv2/imgproc.hpp>
#include <string>

#include "lrd/util/error.h"

namespace lrd::data {

namespace {
std::string describe(const cv::Mat& m) {
  return fmt::format("{}x{} {}", m.cols, m.rows, cv::typeToString(m.type()));
}
}  // namespace

void check_rgbd_input(const cv::Mat& rgb, const cv::Mat& depth, const cv::Mat& mask,
                      const camera::PinholeCamera& cam) {
  if (rgb.empty() || (rgb.type() != CV_8UC3 && rgb.type() != CV_8UC1))
    throw Error(fmt::format("track_rgbd: colour image must be CV_8UC3 or CV_8UC1, got {}", describe(rgb)));
  if (rgb.cols != cam.width || rgb.rows != cam.height)
    throw Error(fmt::format("track_rgbd: colour image is {}x{}, the camera '{}' is {}x{}", rgb.cols, rgb.rows,
                            cam.name, cam.width, cam.height));
  if (depth.size() != rgb.size() || (depth.type() != CV_16UC1 && depth.type() != CV_32FC1))
    throw Error(
        fmt::format("track_rgbd: depth must be CV_16UC1 or CV_32FC1 of the colour image's size, got {}",
                    describe(depth)));
  if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != rgb.size()))
    throw Error(
        fmt::format("track_rgbd: mask must be CV_8UC1 of the colour image's size, got {}", describe(mask)));
}

cv::Mat grey_of(const cv::Mat& rgb, const camera::PinholeCamera& cam) {
  if (rgb.channels() != 3) return rgb;
  cv::Mat grey;
  cv::cvtColor(rgb, grey, cam.rgb_order ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
  return grey;
}

cv::Mat depth_in_metres(const cv::Mat& depth, const camera::PinholeCamera& cam) {
  if (depth.type() != CV_16UC1) return depth;
  cv::Mat metres;
  depth.convertTo(metres, CV_32F, 1.0 / cam.depth_map_factor);
  return metres;
}

cv::Mat bgr_copy_of(const cv::Mat& rgb, const camera::PinholeCamera& cam) {
  cv::Mat bgr;
  if (rgb.channels() == 1)
    cv::cvtColor(rgb, bgr, cv::COLOR_GRAY2BGR);
  else if (cam.rgb_order)
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  else
    bgr = rgb.clone();
  return bgr;
}

}  // namespace lrd::data
