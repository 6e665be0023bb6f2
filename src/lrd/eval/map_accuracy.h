#pragma once
// How good a dense map is against the true surfaces of the scene (the bars in
// bench/results/dense.md): accuracy is the share of map points farther than a threshold from every
// scene sample ("ghosts", e.g. of people), completeness the share of the scene samples the camera
// saw that have a map point within the threshold. Both in the scene's (ground-truth) world frame.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "lrd/camera/pinhole_camera.h"

namespace lrd::eval {

struct MapAccuracy {
  double threshold = 0.05;
  std::size_t map_points = 0;
  std::size_t ghost_points = 0;     // farther than threshold from every scene sample
  double median_distance = 0.0;     // map point to its nearest scene sample (at most threshold)
  std::size_t seen_samples = 0;     // scene samples some frame saw
  std::size_t covered_samples = 0;  // of those, with a map point within threshold
  [[nodiscard]] double ghost_ratio() const {
    return map_points == 0 ? 0.0 : static_cast<double>(ghost_points) / static_cast<double>(map_points);
  }
  [[nodiscard]] double completeness() const {
    return seen_samples == 0 ? 0.0 : static_cast<double>(covered_samples) / static_cast<double>(seen_samples);
  }
};

// One ground-truth view for deciding which scene samples the camera saw.
struct TruthView {
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();
  cv::Mat depth;    // CV_32FC1 metres (the sensor's, people included)
  cv::Mat dynamic;  // CV_8UC1 nonzero where people / moved objects are (or empty)
};

// Marks the samples seen in some view: in the image, at most max_depth away, and on the surface
// the depth image shows there (|z - depth| within 3 cm + 1 % of z), not on a person.
[[nodiscard]] std::vector<char> seen_samples(const std::vector<Eigen::Vector3f>& samples,
                                             const camera::PinholeCamera& camera,
                                             const std::vector<TruthView>& views, double max_depth);

// "0.15 % of 282757 points farther than 5 cm (ghosts), completeness 99.8 % of 32624 seen scene
// samples, median distance 13.1 mm" — what `lrdslam run --dense` and `eval-map` print.
[[nodiscard]] std::string describe(const MapAccuracy& a);

// `map` in the scene's world frame; `seen` from seen_samples (same length as `scene`).
[[nodiscard]] MapAccuracy evaluate_map(const std::vector<Eigen::Vector3f>& map,
                                       const std::vector<Eigen::Vector3f>& scene,
                                       const std::vector<char>& seen, double threshold = 0.05);

}  // namespace lrd::eval
