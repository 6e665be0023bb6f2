#include "lrd/tracking/keyframe_inserter.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "lrd/data/frame.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/map/map_point.h"
#include "lrd/mapping/local_mapper.h"
#include "lrd/tracking/view_coverage.h"

namespace lrd::tracking {

map::MapPoint* add_point_from_depth(map::Map& map, map::KeyFrame* kf, data::Frame& frame, std::size_t i) {
  const auto x = frame.unproject_world(i);
  if (!x) return nullptr;
  map::MapPoint* mp = map.create_map_point(*x, kf, frame.id());
  mp->add_observation(kf, i);
  kf->add_map_point(mp, i);
  mp->compute_distinctive_descriptor();
  mp->update_normal_and_depth();
  frame.map_points[i] = mp;
  return mp;
}

bool KeyFrameInserter::needed(const data::Frame& frame, const KeyFrameContext& context) const {
  const std::size_t n_kfs = map_.keyframe_count();
  const auto max_frames = static_cast<std::uint64_t>(params_.max_frames_between_keyframes > 0
                                                         ? params_.max_frames_between_keyframes
                                                         : static_cast<int>(std::lround(frame.camera().fps)));
  if (context.recovered_at && frame.id() < *context.recovered_at + max_frames && n_kfs > max_frames)
    return false;
  const int min_obs = n_kfs <= 2 ? 2 : 3;
  // The reference's points a person now hides are neither tracked nor lost: counting them would
  // ask for a keyframe each time someone walks past, and its points from depth duplicate the
  // hidden map's (walking_circle, bench/results/scale.md).
  const int hidden =
      params_.discount_hidden_points ? reference_points_hidden(frame, *context.reference, min_obs) : 0;
  const int ref_matches = context.reference->tracked_map_points(min_obs) - hidden;
  const bool idle = mapper_.accepts_keyframes();
  const int inliers = context.inliers;

  // Close points tracked / not tracked: too few tracked and enough new ones means the view has
  // moved on to nearby structure the map lacks.
  int tracked_close = 0, untracked_close = 0;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    if (!frame.is_close(i)) continue;
    if (frame.map_points[i] != nullptr && !frame.outliers[i])
      ++tracked_close;
    else
      ++untracked_close;
  }
  const bool need_close =
      tracked_close < params_.keyframe_close_tracked && untracked_close > params_.keyframe_close_untracked;
  // The tracked points span too little of the view (docs/slam-core.md, "Keyframe coverage").
  const double coverage = params_.keyframe_coverage > 0.0 ? tracked_view_coverage(frame) : 1.0;
  const bool need_coverage = coverage < params_.keyframe_coverage;
  const double ratio = n_kfs < 2 ? 0.4 : params_.reference_ratio;
  const bool c1a = frame.id() >= last_keyframe_frame_id_ + max_frames;
  const bool c1b = frame.id() >= last_keyframe_frame_id_ +
                                     static_cast<std::uint64_t>(params_.min_frames_between_keyframes) &&
                   idle;
  const bool c1c = inliers < ref_matches * 0.25 || need_close;
  // Coverage joins c2 only: its keyframes wait until local mapping is idle (c1b) instead of
  // interrupting it, so the rule adds no mapping load to a busy thread.
  const bool c2 = (inliers < ref_matches * ratio || need_close || need_coverage) && inliers > 15;
  spdlog::debug(
      "frame {}: keyframe? inliers {} ref {} (kf {}, {} hidden) close {}/{} coverage {:.2f} idle {} "
      "c1 {}{}{} c2 {}",
      frame.id(), inliers, ref_matches, context.reference->id(), hidden, tracked_close, untracked_close,
      coverage, idle, c1a, c1b, c1c, c2);
  if (!((c1a || c1b || c1c) && c2)) return false;
  if (idle) return true;
  mapper_.interrupt_ba();
  return mapper_.queued() < static_cast<std::size_t>(mapper_.params().max_queued);
}

map::KeyFrame* KeyFrameInserter::insert(data::Frame& frame) {
  map::KeyFrame* kf = map_.create_keyframe(frame);
  // New map points from depth: all close keypoints without a point, and the nearest far ones
  // until at least keyframe_close_points are covered (ORB-SLAM2's RGB-D CreateNewKeyFrame).
  std::vector<std::pair<float, std::size_t>> by_depth;
  for (std::size_t i = 0; i < frame.size(); ++i)
    if (frame.depth(i) > 0.0f) by_depth.emplace_back(frame.depth(i), i);
  std::sort(by_depth.begin(), by_depth.end());
  const double close = frame.camera().close_depth_threshold();
  int covered = 0;
  for (const auto& [d, i] : by_depth) {
    map::MapPoint* mp = frame.map_points[i];
    if (mp == nullptr || mp->num_observations() < 1) {
      add_point_from_depth(map_, kf, frame, i);
      frame.outliers[i] = false;
    }
    ++covered;
    if (d > close && covered > params_.keyframe_close_points) break;
  }
  mapper_.insert_keyframe(kf);
  last_keyframe_frame_id_ = frame.id();
  return kf;
}

void KeyFrameInserter::inserted_first(const data::Frame& frame) {
  last_keyframe_frame_id_ = frame.id();
}

}  // namespace lrd::tracking
