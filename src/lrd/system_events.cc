// lrd::System's publishing: a tracked frame (and the keyframe it became) as events.
#include <vector>

#include "lrd/data/frame.h"
#include "lrd/system_impl.h"

namespace lrd {

namespace {
std::vector<cv::Point2f> points_of(const std::vector<cv::KeyPoint>& keypoints) {
  std::vector<cv::Point2f> out;
  out.reserve(keypoints.size());
  for (const cv::KeyPoint& k : keypoints) out.push_back(k.pt);
  return out;
}
}  // namespace

void System::Impl::publish_frame(const TrackResult& r, const tracking::TrackOutcome& outcome,
                                 const data::Frame& frame, const cv::Mat& grey, bool grey_shared) {
  events::FrameTracked e;
  e.map = pipe->generation;
  e.frame_id = frame.id();
  e.timestamp = frame.timestamp();
  e.state = r.state;
  e.T_wc = r.T_wc;
  e.timing = r.timing;
  e.inliers = r.inliers;
  e.mask_frame = r.dynamic.mask_frame;
  e.mask_age = r.dynamic.mask_age;
  e.geometric_keypoints = r.dynamic.geometric_keypoints;
  e.relocalized = outcome.relocalized;
  if (outcome.new_keyframe != nullptr) e.new_keyframe = outcome.new_keyframe_id;
  e.grey = grey_shared ? grey.clone() : grey;  // the caller may reuse its buffer
  e.mask = r.dynamic.mask.empty() ? cv::Mat() : r.dynamic.mask.clone();
  e.kept_keypoints = points_of(frame.keypoints());
  e.removed_keypoints = points_of(frame.removed_keypoints);
  publisher.publish(std::move(e));
}

}  // namespace lrd
