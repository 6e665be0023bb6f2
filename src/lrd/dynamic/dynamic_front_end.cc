#include "lrd/dynamic/dynamic_front_end.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/core.hpp>

#include "lrd/data/frame.h"
#include "lrd/dynamic/mask_propagator.h"
#include "lrd/segmentation/mask_folder_segmenter.h"
#include "lrd/segmentation/onnx_segmenter.h"
#include "lrd/segmentation/segmentation_worker.h"
#include "lrd/util/error.h"
#include "lrd/util/exception_message.h"

namespace lrd::dynamic {

namespace {
// How many frames back a mask can be carried over from (the history of the frames the network saw).
constexpr std::size_t kRecentFrames = 30;

std::unique_ptr<segmentation::Segmenter> make_segmenter(const segmentation::SegmentationParams& p) {
  switch (p.backend) {
    case segmentation::Backend::Onnx:
      return std::make_unique<segmentation::OnnxSegmenter>(p.onnx);
    case segmentation::Backend::Masks:
      return std::make_unique<segmentation::MaskFolderSegmenter>(p.masks);
    case segmentation::Backend::None:
      break;
  }
  return nullptr;
}
}  // namespace

DynamicFrontEnd::DynamicFrontEnd(DynamicParams params, segmentation::SegmentationParams segmentation,
                                 const camera::PinholeCamera& camera)
    : params_(params), segmentation_(std::move(segmentation)), camera_(camera), filter_(params_.geometry) {
  if (!dynamic::uses_segmentation(params_.mode)) return;
  if (segmentation_.backend == segmentation::Backend::None)
    throw Error("mode '" + to_string(params_.mode) +
                "' needs a segmentation backend (segmentation.backend: onnx or masks; or --segmenter)");
  worker_ = std::make_unique<segmentation::SegmentationWorker>(make_segmenter(segmentation_),
                                                               segmentation_.schedule, camera_.rgb_order);
}

DynamicFrontEnd::~DynamicFrontEnd() = default;

void DynamicFrontEnd::shutdown() {
  if (worker_) worker_->shutdown();
}

std::string DynamicFrontEnd::segmentation_description() const {
  if (!worker_) return "none";
  return worker_->segmenter().describe() + ", " + segmentation::to_string(worker_->schedule());
}

bool DynamicFrontEnd::network_sees(std::uint64_t id) const {
  return segmentation_.schedule == segmentation::Schedule::Sync ||
         id % static_cast<std::uint64_t>(segmentation_.stride) == 0;
}

void DynamicFrontEnd::submit(std::uint64_t id, double timestamp, const cv::Mat& rgb) {
  if (worker_ && network_sees(id)) worker_->submit(id, timestamp, rgb.clone());
}

SemanticMask DynamicFrontEnd::mask(std::uint64_t id, const cv::Mat& depth,
                                   const std::optional<Eigen::Isometry3d>& predicted_T_cw) {
  current_depth_ = depth;
  SemanticMask out;
  if (!worker_) return out;
  // Until the first mask a frame waits for its own, as in sync: the map is built on the first
  // frames, and what they put there on people stays (async FNet-lite's cold first run missed its
  // deadline, and walking_rpy's first keyframe made a walker an obstacle in the occupancy map).
  const bool sync =
      segmentation_.schedule == segmentation::Schedule::Sync || (!had_mask_ && network_sees(id));
  // A frame the network was not given (async stride) takes the newest mask without waiting.
  std::optional<segmentation::SegmentationResult> result;
  try {
    result = worker_->wait(
        id, sync ? std::nullopt
                 : std::optional<double>(network_sees(id) ? segmentation_.max_wait_ms / 1000.0 : 0.0));
  } catch (...) {
    throw Error(fmt::format("segmentation thread: {}", util::exception_message(std::current_exception())));
  }
  if (!result) return out;
  had_mask_ = true;
  const auto age = static_cast<int>(id - result->frame_id);
  out.mask_frame = static_cast<std::int64_t>(result->frame_id);
  out.mask_age = age;
  out.segmentation_seconds = result->seconds;
  int dilation = segmentation_.dilation_px;
  cv::Mat mask;
  if (age > 0) {
    dilation += std::min(segmentation_.max_age_dilation_px,
                         static_cast<int>(std::lround(age * segmentation_.age_dilation_px)));
    const auto it = std::find_if(recent_.begin(), recent_.end(),
                                 [&](const RecentFrame& r) { return r.id == result->frame_id; });
    if (predicted_T_cw && it != recent_.end() && it->T_cw)
      mask = carry_mask(result->mask, it->depth, *predicted_T_cw * it->T_cw->inverse(), camera_, dilation);
  }
  if (mask.empty()) mask = dilated_mask(result->mask, dilation);  // a new buffer: the worker keeps its mask
  out.mask = mask;
  return out;
}

GeometryStats DynamicFrontEnd::remove_moving_points(data::Frame& f,
                                                    const std::vector<map::KeyFrame*>& nearby) {
  const auto t0 = std::chrono::steady_clock::now();
  // In geometric mode nothing was filtered before the first estimate: judge from a pose the
  // moving objects cannot drag, and start the final optimization from it.
  if (params_.mode == DynamicMode::Geometric) {
    int inliers = 0;
    const auto T = filter_.robust_pose(f, &inliers);
    spdlog::debug("frame {}: robust pose {} ({} inliers)", f.id(), T ? "ok" : "failed", inliers);
    if (T) f.set_pose(*T);
  }
  GeometryCheckResult r = filter_.check(f, current_depth_, nearby);
  // In full mode the pose the check judged from rests on the frame's matches with a map the
  // segmentation kept people out of; a check that finds most of them moving contradicts its own
  // premise (bench/results/log/bonn.md, person_tracking: static foreground hiding mapped points of
  // a wall seen at a grazing angle, regions grown along the wall over most of the frame). The
  // semantic mask still applies. Not in geometric mode: there a person the camera follows is mapped
  // and matched like the room, and flagging them is right.
  if (params_.mode == DynamicMode::Full && flags_most_pose_matches(f, r.dynamic)) {
    spdlog::debug(
        "frame {}: geometry check found {} keypoints moving, most of the matches the pose rests on: "
        "not applied",
        f.id(), r.flagged_keypoints);
    r = GeometryCheckResult{};
    r.dynamic.assign(f.size(), false);
  }
  if (r.flagged_keypoints > 0) f.remove_keypoints(r.dynamic);
  if (!r.mask.empty()) {
    if (f.dynamic_mask.empty()) {
      f.dynamic_mask = r.mask;
    } else {
      cv::Mat merged;  // a new buffer: the frame's mask may share the caller's
      cv::bitwise_or(f.dynamic_mask, r.mask, merged);
      f.dynamic_mask = merged;
    }
  }
  spdlog::debug(
      "frame {}: geometry check: {} keyframes, {} judged, {} moving, {} skipped (parallax), {} "
      "keypoints removed",
      f.id(), r.keyframes, r.judged, r.seeds, r.parallax_skipped, r.flagged_keypoints);
  GeometryStats stats;
  stats.keypoints_removed = r.flagged_keypoints;
  stats.seeds = r.seeds;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

void DynamicFrontEnd::frame_done(std::uint64_t id, const std::optional<Eigen::Isometry3d>& T_cw,
                                 cv::Mat own_depth) {
  // Only a carried-over mask needs the history, and only from the frames the network was given.
  if (worker_) {
    if (keeps_depth_of(id)) recent_.push_back({id, own_depth.empty() ? current_depth_ : own_depth, T_cw});
    while (!recent_.empty() && recent_.front().id + kRecentFrames <= id) recent_.pop_front();
  }
  current_depth_ = cv::Mat();
}

}  // namespace lrd::dynamic
