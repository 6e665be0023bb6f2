#pragma once
// The features of one RGB-D image, ready for tracking (ORB-SLAM2's Frame, RGB-D case): ORB
// keypoints and descriptors (extracted once, dynamic pixels masked out before description),
// their undistorted positions in a grid for fast area search, a depth per keypoint and the
// virtual right coordinate u_R = u - bf/d that lets RGB-D observations act as stereo ones.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/features/keypoint_undistorter.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/geometry/se3.h"
#include "lrd/place/bow_vector.h"

namespace lrd::map {
class MapPoint;
}  // namespace lrd::map
namespace lrd::place {
class Vocabulary;
}

namespace lrd::data {

class Frame {
 public:
  static constexpr int kGridCols = 64;
  static constexpr int kGridRows = 48;

  enum class Extraction {
    Full,              // the extractor runs on `grey` now
    DescribeDetected,  // extractor.detect(grey) already ran; only the description is left
  };

  // `grey` CV_8UC1; `depth` CV_32FC1 metres (0 = invalid), registered to `grey`; `mask` CV_8UC1
  // (nonzero = dynamic, no features there) or empty.
  Frame(std::uint64_t id, double timestamp, const cv::Mat& grey, const cv::Mat& depth, const cv::Mat& mask,
        features::OrbExtractor& extractor, const features::KeypointUndistorter& undistorter,
        const camera::PinholeCamera& camera, Extraction extraction = Extraction::Full);

  // What a map file keeps of a keyframe's features (map/map_file.h): no images, no grid (rebuilt).
  struct SavedFeatures {
    std::vector<cv::KeyPoint> keypoints, undistorted;
    cv::Mat descriptors;  // N x 32 CV_8U
    std::vector<float> depth, u_right;
    std::vector<float> level_sigma2, inv_level_sigma2, scale_factors;
    cv::Rect2f bounds;
  };
  // A frame restored from saved features, with its pose. Throws lrd::Error when the arrays'
  // sizes disagree.
  Frame(std::uint64_t id, double timestamp, const camera::PinholeCamera& camera, SavedFeatures features,
        const Eigen::Isometry3d& T_cw);
  [[nodiscard]] SavedFeatures saved_features() const;

  // Removes the keypoints with drop[i] set (dynamic ones found after extraction, paper
  // Algorithm 1), with their descriptors, depths and matches; the grid is rebuilt.
  void remove_keypoints(const std::vector<bool>& drop);
  // Moves the keypoints' undistorted positions and depths (one of each per keypoint, depth <= 0:
  // none), e.g. to where a rolling shutter would have seen them at the stamp; the detected
  // positions stay as they were. The grid is rebuilt.
  void move_keypoints(const std::vector<cv::Point2f>& undistorted, const std::vector<float>& depth);

  [[nodiscard]] std::uint64_t id() const { return id_; }
  [[nodiscard]] double timestamp() const { return timestamp_; }
  [[nodiscard]] std::size_t size() const { return keypoints_.size(); }
  [[nodiscard]] const camera::PinholeCamera& camera() const { return camera_; }

  [[nodiscard]] const std::vector<cv::KeyPoint>& keypoints() const { return keypoints_; }  // as detected
  [[nodiscard]] const std::vector<cv::KeyPoint>& undistorted() const {
    return undistorted_;
  }  // ideal pinhole
  [[nodiscard]] const cv::Mat& descriptors() const { return descriptors_; }
  [[nodiscard]] float depth(std::size_t i) const { return depth_[i]; }      // metres, < 0 = none
  [[nodiscard]] float u_right(std::size_t i) const { return u_right_[i]; }  // < 0 = none
  // Close points (depth < ThDepth baselines) are reliable enough to create map points alone.
  [[nodiscard]] bool is_close(std::size_t i) const { return depth_[i] > 0 && depth_[i] < close_depth_; }
  [[nodiscard]] const std::vector<float>& level_sigma2() const { return level_sigma2_; }
  [[nodiscard]] const std::vector<float>& inv_level_sigma2() const { return inv_level_sigma2_; }
  [[nodiscard]] const std::vector<float>& scale_factors() const { return scale_factors_; }

  // Indices of keypoints whose undistorted position lies within `radius` pixels (square window,
  // as ORB-SLAM2) of (x, y), on pyramid levels [min_level, max_level] (< 0: no bound).
  [[nodiscard]] std::vector<std::size_t> features_in_area(float x, float y, float radius, int min_level = -1,
                                                          int max_level = -1) const;
  // The same into `out` (replaced): a loop over many points reuses one buffer, no allocation each.
  void features_in_area(float x, float y, float radius, int min_level, int max_level,
                        std::vector<std::size_t>& out) const;

  // Whether an undistorted position lies inside the image (the undistorted bounds).
  [[nodiscard]] bool in_bounds(double u, double v) const {
    return u >= bounds_.x && u < bounds_.x + bounds_.width && v >= bounds_.y &&
           v < bounds_.y + bounds_.height;
  }
  [[nodiscard]] const cv::Rect2f& bounds() const { return bounds_; }

  // Tracking's working state: the map point matched to each keypoint (nullptr: none) and whether
  // the last pose optimization rejected that match.
  std::vector<map::MapPoint*> map_points;
  std::vector<bool> outliers;
  // Pixels judged dynamic (CV_8UC1, nonzero; empty: none): the segmentation mask and the
  // geometric check's regions. Kept with keyframes for mapping, loop closing and the dense map.
  cv::Mat dynamic_mask;
  // Keypoints remove_keypoints() took out (as detected), for viewers: what the dynamic checks
  // removed after extraction (those under the segmentation mask are never extracted).
  std::vector<cv::KeyPoint> removed_keypoints;

  // Bag-of-words of the descriptors (relocalization, loop closing); empty until compute_bow().
  // bow_features groups keypoints by vocabulary node kBowLevelsUp levels above the words, the
  // direct index that restricts descriptor matching to keypoints under the same node: with the
  // shipped 5-level vocabulary, the 100 nodes of depth 2 (as ORB-SLAM2's 4 up from its 6 levels).
  static constexpr int kBowLevelsUp = 3;
  void compute_bow(const place::Vocabulary& vocabulary);
  // compute_bow in two steps, for a caller that transforms without holding the map and stores the
  // result while holding it: words() reads only the descriptors; set_words() keeps words the frame
  // has already.
  struct Words {
    place::BowVector bow;
    place::FeatureVector features;
  };
  [[nodiscard]] Words words(const place::Vocabulary& vocabulary) const;
  void set_words(Words words);
  [[nodiscard]] bool has_bow() const { return !bow.empty(); }
  place::BowVector bow;
  place::FeatureVector bow_features;

  void set_pose(const Eigen::Isometry3d& T_cw) { T_cw_ = geometry::orthonormalized(T_cw); }
  [[nodiscard]] bool has_pose() const { return T_cw_.has_value(); }
  [[nodiscard]] const Eigen::Isometry3d& T_cw() const { return *T_cw_; }
  [[nodiscard]] Eigen::Isometry3d T_wc() const { return T_cw_->inverse(); }
  // World point of keypoint i from its depth; empty without depth or pose.
  [[nodiscard]] std::optional<Eigen::Vector3d> unproject_world(std::size_t i) const;
  // Heap bytes this frame holds (its features, grid, bag of words, images), for memory figures.
  [[nodiscard]] std::size_t memory_bytes() const;

 private:
  [[nodiscard]] bool grid_cell(const cv::Point2f& p, int& col, int& row) const;
  void build_grid();

  std::uint64_t id_;
  double timestamp_;
  camera::PinholeCamera camera_;
  std::vector<cv::KeyPoint> keypoints_, undistorted_;
  cv::Mat descriptors_;
  std::vector<float> depth_, u_right_;
  float close_depth_;
  std::vector<float> level_sigma2_, inv_level_sigma2_, scale_factors_;
  cv::Rect2f bounds_;
  float cell_w_inv_, cell_h_inv_;
  // kGridCols * kGridRows cells, row-major: cell k holds grid_index_[grid_start_[k], grid_start_[k+1]).
  std::vector<std::uint32_t> grid_start_, grid_index_;
  std::optional<Eigen::Isometry3d> T_cw_;
};

}  // namespace lrd::data
