#pragma once
// ORB features (Rublee et al. 2011) as the SLAM core needs them, in the manner of ORB-SLAM2's
// extractor (Mur-Artal & Tardos 2017): FAST corners on every level of a scale pyramid, found per
// grid cell with a high threshold and a low fallback, spread by a quadtree to the requested
// count, oriented by the intensity centroid and described by 256-bit steered BRIEF.
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "lrd/features/fast_scores.h"
#include "lrd/features/gaussian_smoother.h"
#include "lrd/features/image_pyramid.h"
#include "lrd/features/orb_params.h"
#include "lrd/features/quadtree_distributor.h"

namespace lrd::features {

class OrbExtractor {
 public:
  // Throws lrd::Error for invalid parameters.
  explicit OrbExtractor(const OrbParams& params);

  // Keypoints of `grey` (CV_8UC1) in level-0 pixel coordinates, with octave (pyramid level),
  // angle (degrees, [0, 360)), size (patch diameter at level 0) and response (FAST score) set,
  // and their descriptors (N x 32 CV_8U, row i for keypoint i). Keypoints come in level order.
  // `mask` (CV_8UC1, same size, may be empty): a nonzero pixel is excluded, no keypoint lies on
  // it and none is described there; the budget goes to the rest of the image. Same input, same
  // output bits. Pyramid levels are processed in parallel (TBB) and assembled in level order. One
  // extractor per calling thread: it keeps its buffers between calls.
  void extract(const cv::Mat& grey, const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints,
               cv::Mat& descriptors);

  // The same in two phases, for a mask that arrives while corners are being found (the
  // segmentation thread runs meanwhile): detect() builds the pyramid and finds the FAST corners
  // of the whole image; describe_detected() drops those under `mask`, spreads the rest and
  // describes them. The result equals extract()'s except in grid cells whose strong corners are
  // all masked, which then get no low-threshold fallback.
  void detect(const cv::Mat& grey);
  void describe_detected(const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors);

  [[nodiscard]] const OrbParams& params() const { return params_; }
  [[nodiscard]] int levels() const { return params_.n_levels; }
  // Per level: scale_factor^i, its inverse, its square (the variance of a keypoint's position at
  // level 0 in pixels^2, as ORB-SLAM2's mvLevelSigma2) and that inverse.
  [[nodiscard]] const std::vector<float>& scale_factors() const { return pyramid_.scale_factors(); }
  [[nodiscard]] const std::vector<float>& inv_scale_factors() const { return pyramid_.inv_scale_factors(); }
  [[nodiscard]] const std::vector<float>& level_sigma2() const { return sigma2_; }
  [[nodiscard]] const std::vector<float>& inv_level_sigma2() const { return inv_sigma2_; }
  // Keypoints asked of each level (geometric in 1/scale_factor, as ORB-SLAM2).
  [[nodiscard]] const std::vector<int>& features_per_level() const { return per_level_; }
  // The pyramid of the last extract() call (level 0 refers to that call's image).
  [[nodiscard]] const ImagePyramid& pyramid() const { return pyramid_; }

  static constexpr int kPatchSize = 31;  // orientation and descriptor patch diameter
  static constexpr int kEdge = 19;       // no keypoint closer than this to a level's border
  static constexpr int kCellSize = 30;   // FAST threshold cells, level pixels
  static constexpr int kDescriptorBits = 256;
  static constexpr int kDescriptorBytes = kDescriptorBits / 8;

  // The orientation disc as weights over 32-pixel rows from -kPatchSize / 2, one per row offset
  // -kPatchSize / 2 .. kPatchSize / 2: a column's u inside the disc (0 outside), and 1 inside.
  struct DiscWeights {
    std::int16_t u[kPatchSize][32];
    std::int16_t inside[kPatchSize][32];
  };
  static_assert(kPatchSize < 32);

 private:
  // What one pyramid level works with; levels run in parallel, each on its own.
  struct LevelWork {
    FastScores scores;                         // every pixel's FAST score, both thresholds read it
    std::vector<cv::KeyPoint> corners, found;  // FAST output, level coordinates
    std::vector<cv::KeyPoint> chosen;          // after the quadtree, level coordinates
    std::vector<char> cell_strong;
    GaussianSmoother smoother;
    cv::Mat smoothed;
    std::vector<cv::KeyPoint> keypoints;  // the chosen ones described: level-0 coordinates
    cv::Mat descriptors;                  // one row per keypoint
  };

  // Unmasked FAST corners of one level (level coordinates, response = score): those scoring
  // ini_th_fast, and in cells without any, those scoring min_th_fast.
  void detect(int level, const cv::Mat& mask, LevelWork& work) const;
  // Builds the pyramid, finds every level's corners (detect) and smooths every level.
  void detect_and_smooth(const cv::Mat& grey, const cv::Mat& mask);
  void check_input(const cv::Mat& grey, const cv::Mat& mask) const;
  // Orientation and description of level `level`'s chosen corners into its keypoints, descriptors.
  void describe_chosen(int level);
  // Quadtree distribution, orientation and description of the detected corners not under `mask`.
  void finish(const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors);

  OrbParams params_;
  ImagePyramid pyramid_;
  QuadtreeDistributor distributor_;
  std::vector<float> sigma2_, inv_sigma2_;
  std::vector<int> per_level_;
  DiscWeights disc_{};
  std::array<float, 2 * kDescriptorBits> pattern_x_, pattern_y_;  // brief_pattern(), point by point
  std::vector<LevelWork> work_;                                   // kept between calls
};

}  // namespace lrd::features
