#pragma once
// The multi-view geometry check (paper §2.7, Fig. 5; DynaSLAM's test): keypoints with depth of
// the keyframes that overlap most with the current frame are projected into it with the first
// pose estimate. A static point lands where the current depth says it should; when something
// now stands in front of it (projected depth z_proj exceeds the measured z' by more than tau_z,
// agreed by the depth patch around it), the pixel belongs to a moving object. Points seen at a
// parallax above 30 degrees are not judged: the difference may be plain occlusion. The flagged
// pixels are grown into regions on the depth image, and every keypoint of the frame inside
// them is dynamic.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "lrd/dynamic/dynamic_params.h"

namespace lrd::data {
class Frame;
}
namespace lrd::map {
class KeyFrame;
}

namespace lrd::dynamic {

struct GeometryCheckResult {
  cv::Mat mask;               // CV_8UC1 full size, 255 = moving (empty: nothing flagged)
  std::vector<bool> dynamic;  // per keypoint of the frame
  int keyframes = 0;          // keyframes compared
  int judged = 0;             // projected points with a valid depth to compare
  int seeds = 0;              // of those, flagged as moving
  int parallax_skipped = 0;   // not judged: parallax above the limit
  int flagged_keypoints = 0;
};

// Whether `dynamic` (per keypoint of `frame`) takes more than half of the inlier map matches the
// frame's pose rests on, once there are at least 30 of them. A moving object has few: it was
// masked, or elsewhere, when the map was built. A check that flags most of them is wrong itself.
[[nodiscard]] bool flags_most_pose_matches(const data::Frame& frame, const std::vector<bool>& dynamic);

class DynamicPointFilter {
 public:
  explicit DynamicPointFilter(GeometryCheckParams params) : params_(params) {}

  // `frame` must have its first pose estimate; `depth` is its CV_32FC1 depth in metres;
  // `candidates` the keyframes near it (the tracker's local keyframes). Map mutex held.
  [[nodiscard]] GeometryCheckResult check(const data::Frame& frame, const cv::Mat& depth,
                                          const std::vector<map::KeyFrame*>& candidates) const;

  // The `keyframes` candidates overlapping most with a camera at T_cw (nearest in position and
  // viewing direction), at least min_keyframe_age_s older than `timestamp`.
  [[nodiscard]] std::vector<map::KeyFrame*> select_keyframes(
      const Eigen::Isometry3d& T_cw, double timestamp, const std::vector<map::KeyFrame*>& candidates) const;

  // A pose for the check that moving objects cannot drag (paper §2.7 asks for a first estimate
  // on filtered features; in geometric mode nothing is filtered yet, and people that walk
  // coherently bias the motion-only optimization by centimetres per frame): PnP RANSAC on the
  // frame's map-point matches, from the current estimate, keeping the dominant rigid motion.
  // Empty when too few matches agree. OpenCV's RANSAC seeds its own generator: deterministic.
  [[nodiscard]] std::optional<Eigen::Isometry3d> robust_pose(const data::Frame& frame,
                                                             int* inliers = nullptr) const;

  [[nodiscard]] const GeometryCheckParams& params() const { return params_; }

 private:
  GeometryCheckParams params_;
};

}  // namespace lrd::dynamic
