#include "lrd/runner/localization_latency.h"

#include <algorithm>
#include <cmath>

#include "lrd/eval/association.h"
#include "lrd/eval/ate.h"

namespace lrd::runner {

namespace {

// Map points the true camera sees unhidden in `depth` (CV_32FC1 metres).
std::size_t points_in_view(const std::vector<Eigen::Vector3d>& points_gt, const Eigen::Isometry3d& T_wc,
                           const cv::Mat& depth, const camera::PinholeCamera& cam) {
  const Eigen::Isometry3d T_cw = T_wc.inverse();
  std::size_t seen = 0;
  for (const Eigen::Vector3d& p : points_gt) {
    const Eigen::Vector3d c = T_cw * p;
    if (c.z() <= 0.1) continue;
    const Eigen::Vector2d uv = cam.project(c);
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) continue;
    const float d = depth.at<float>(v, u);
    seen += d > 0.0f && std::abs(d - c.z()) < 0.1 * c.z();
  }
  return seen;
}

}  // namespace

LocalizationLatency localization_latency(const std::vector<Eigen::Vector3d>& map_points,
                                         const std::vector<tracking::TrackingState>& states,
                                         const io::FrameSource& source, const io::Trajectory& ground_truth,
                                         const Eigen::Isometry3d& ground_truth_from_map,
                                         const camera::PinholeCamera& camera, std::size_t min_points) {
  LocalizationLatency latency;
  const auto localized = std::find(states.begin(), states.end(), tracking::TrackingState::Ok);
  if (localized != states.end())
    latency.first_localized_frame = static_cast<std::size_t>(localized - states.begin());

  std::vector<Eigen::Vector3d> points_gt;
  points_gt.reserve(map_points.size());
  for (const Eigen::Vector3d& p : map_points) points_gt.push_back(ground_truth_from_map * p);
  io::Trajectory frames;
  for (std::size_t i = 0; i < states.size() && i < source.size(); ++i)
    frames.push_back({source.entry(i).timestamp, Eigen::Isometry3d::Identity()});
  // Each frame's true pose: the ground truth associated with its stamp (TUM's 20 ms).
  const std::vector<eval::Match> matches =
      eval::associate(eval::timestamps(frames), eval::timestamps(ground_truth), 0.02);
  for (const eval::Match& m : matches) {
    const cv::Mat depth = source.load_rgbd(m.first, camera.depth_map_factor).depth;
    if (points_in_view(points_gt, ground_truth[m.second].pose, depth, camera) >= min_points) {
      latency.first_view_frame = m.first;
      break;
    }
  }
  return latency;
}

}  // namespace lrd::runner
