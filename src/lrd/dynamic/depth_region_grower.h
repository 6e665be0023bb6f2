#pragma once
// Grows single points flagged as moving into the regions of the objects they lie on (paper
// §2.7: the whole moving object is masked, not only the sampled pixels): a flood fill over the
// depth image that follows smooth depth and stays within a depth band and a lateral extent of
// its seed, so it does not run on along the floor the object stands on.
#include <opencv2/core.hpp>
#include <vector>

namespace lrd::dynamic {

struct RegionSeed {
  float u = 0.0f, v = 0.0f;  // pixel (full resolution)
  float depth = 0.0f;        // metres
};

struct RegionGrowParams {
  double step = 0.03;   // neighbour-to-neighbour depth difference, metres (+ 1 % of depth)
  double band = 0.35;   // largest depth difference to the seed, metres
  double extent = 0.8;  // largest sideways distance to the seed, metres (x 1.5 vertically)
};

// Works on a half-resolution copy of `depth` (CV_32FC1 metres) for speed; returns a full-size
// CV_8UC1 mask, 255 inside the grown regions. fx, fy: the camera's focal lengths (full size).
[[nodiscard]] cv::Mat grow_regions(const cv::Mat& depth, const std::vector<RegionSeed>& seeds, double fx,
                                   double fy, const RegionGrowParams& params);

}  // namespace lrd::dynamic
