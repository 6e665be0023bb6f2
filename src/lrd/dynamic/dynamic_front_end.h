#pragma once
// The dynamic front end (paper §2.5-2.7, Fig. 1): everything that decides which pixels of a frame
// belong to moving objects before its pose is estimated. It owns
//  - the segmentation thread and its schedule (sync, or async with a stride),
//  - the recent frames' depth and poses, to carry an older mask over to the current frame along
//    the predicted motion (mask propagation) and to dilate it by its age,
//  - the multi-view geometry check with region growing (DynamicPointFilter).
// Per frame, in the tracking thread:
//   submit(id, t, rgb)                    the network starts on the frame (while ORB runs)
//   mask(id, depth, predicted pose)       the frame's semantic mask, with its statistics
//   remove_moving_points(frame, nearby)   called by Tracker after the first pose estimate
//   frame_done(id, pose)                  the frame joins the history
// The geometry check cannot run in one call with the rest: it needs the first pose estimate,
// which only tracking makes; Tracker calls it through MovingPointCheck.
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/dynamic/dynamic_params.h"
#include "lrd/dynamic/dynamic_point_filter.h"
#include "lrd/dynamic/moving_point_check.h"
#include "lrd/segmentation/segmentation_params.h"

namespace lrd::segmentation {
class SegmentationWorker;
}

namespace lrd::dynamic {

// The segmentation mask a frame gets.
struct SemanticMask {
  cv::Mat mask;                       // CV_8UC1, nonzero = dynamic, dilated (empty: none yet)
  std::int64_t mask_frame = -1;       // the frame the network saw (-1: none)
  int mask_age = -1;                  // frames between that frame and this one (-1: none)
  double segmentation_seconds = 0.0;  // the network's time on it (its own thread)
};

class DynamicFrontEnd final : public MovingPointCheck {
 public:
  // Starts the segmentation thread when the mode uses segmentation (the backend must be set).
  DynamicFrontEnd(DynamicParams params, segmentation::SegmentationParams segmentation,
                  const camera::PinholeCamera& camera);
  ~DynamicFrontEnd() override;
  DynamicFrontEnd(const DynamicFrontEnd&) = delete;
  DynamicFrontEnd& operator=(const DynamicFrontEnd&) = delete;

  [[nodiscard]] DynamicMode mode() const { return params_.mode; }
  [[nodiscard]] bool uses_segmentation() const { return worker_ != nullptr; }
  // The geometry check for Tracker, or null when the mode has none.
  [[nodiscard]] MovingPointCheck* moving_point_check() {
    return dynamic::uses_geometry(params_.mode) ? this : nullptr;
  }
  // "masks (seq/mask), async" or "none".
  [[nodiscard]] std::string segmentation_description() const;

  // Frame `id` arrived: the network starts on it when the schedule gives it this frame. The
  // image is copied (the caller may reuse its buffer while the network reads).
  void submit(std::uint64_t id, double timestamp, const cv::Mat& rgb);
  // The semantic mask for frame `id` (sync: its own; async: the newest within the wait bound,
  // carried over along `predicted_T_cw`); `depth` (CV_32FC1 metres) is kept for the geometry
  // check and the history (see frame_done).
  [[nodiscard]] SemanticMask mask(std::uint64_t id, const cv::Mat& depth,
                                  const std::optional<Eigen::Isometry3d>& predicted_T_cw);
  GeometryStats remove_moving_points(data::Frame& frame, const std::vector<map::KeyFrame*>& nearby) override;
  // Whether frame_done keeps frame `id`'s depth: only a frame the network is given can lend its
  // mask to a later one (the carry-over reads the mask's own depth).
  [[nodiscard]] bool keeps_depth_of(std::uint64_t id) const { return worker_ != nullptr && network_sees(id); }
  // Frame `id` is tracked (T_cw) or lost (empty). `own_depth`: the frame's depth for the history
  // when the one given to mask() is the caller's buffer (empty: keep that one).
  void frame_done(std::uint64_t id, const std::optional<Eigen::Isometry3d>& T_cw, cv::Mat own_depth = {});

  // Stops the segmentation thread. Idempotent.
  void shutdown();

 private:
  struct RecentFrame {
    std::uint64_t id = 0;
    cv::Mat depth;
    std::optional<Eigen::Isometry3d> T_cw;
  };
  [[nodiscard]] bool network_sees(std::uint64_t id) const;

  DynamicParams params_;
  segmentation::SegmentationParams segmentation_;
  camera::PinholeCamera camera_;
  DynamicPointFilter filter_;
  std::unique_ptr<segmentation::SegmentationWorker> worker_;
  std::deque<RecentFrame> recent_;
  cv::Mat current_depth_;
  bool had_mask_ = false;  // a mask has come back from the network
};

}  // namespace lrd::dynamic
