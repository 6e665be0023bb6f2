#include "lrd/dynamic/dynamic_point_filter.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "lrd/data/frame.h"
#include "lrd/dynamic/depth_region_grower.h"
#include "lrd/map/keyframe.h"

namespace lrd::dynamic {

std::vector<map::KeyFrame*> DynamicPointFilter::select_keyframes(const Eigen::Isometry3d& T_cw, double timestamp,
                                                                 const std::vector<map::KeyFrame*>& candidates) const {
  const Eigen::Vector3d centre = T_cw.inverse().translation();
  std::vector<std::pair<double, map::KeyFrame*>> scored;
  for (map::KeyFrame* kf : candidates) {
    if (kf == nullptr || kf->is_bad() || timestamp - kf->timestamp() < params_.min_keyframe_age_s) continue;
    // Overlap falls with distance and with the angle between the viewing directions; 0.5 m
    // weighs as much as 1 rad (~57 deg).
    const double distance = (kf->camera_center() - centre).norm();
    const double angle = Eigen::AngleAxisd(T_cw.linear() * kf->T_cw().linear().transpose()).angle();
    scored.emplace_back(distance + 0.5 * angle, kf);
  }
  std::sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second->id() < b.second->id();
  });
  std::vector<map::KeyFrame*> out;
  for (std::size_t i = 0; i < scored.size() && static_cast<int>(i) < params_.keyframes; ++i)
    out.push_back(scored[i].second);
  return out;
}

GeometryCheckResult DynamicPointFilter::check(const data::Frame& frame, const cv::Mat& depth,
                                              const std::vector<map::KeyFrame*>& candidates) const {
  GeometryCheckResult r;
  r.dynamic.assign(frame.size(), false);
  const camera::PinholeCamera& cam = frame.camera();
  const Eigen::Isometry3d& T_cw = frame.T_cw();
  const Eigen::Vector3d centre = T_cw.inverse().translation();
  const double cos_limit = std::cos(params_.max_parallax_deg * std::numbers::pi / 180.0);
  const int n = params_.neighbourhood;
  std::vector<RegionSeed> seeds;

  const auto keyframes = select_keyframes(T_cw, frame.timestamp(), candidates);
  r.keyframes = static_cast<int>(keyframes.size());
  for (const map::KeyFrame* kf : keyframes) {
    const data::Frame& f = kf->features();
    const Eigen::Isometry3d T_w_kf = kf->T_wc();
    const Eigen::Vector3d kf_centre = T_w_kf.translation();
    for (std::size_t i = 0; i < f.size(); ++i) {
      const float z_kf = f.depth(i);
      if (z_kf <= 0.0f || z_kf > params_.max_depth) continue;
      const cv::Point2f& p = f.undistorted()[i].pt;
      const Eigen::Vector3d X = T_w_kf * cam.unproject(p.x, p.y, z_kf);
      const Eigen::Vector3d Xc = T_cw * X;
      const double z_proj = Xc.z();
      if (z_proj <= 0.1 || z_proj > params_.max_depth) continue;
      const Eigen::Vector2d uv = cam.project(Xc);
      const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
      if (u < n || v < n || u >= depth.cols - n || v >= depth.rows - n) continue;
      const float z_now = depth.at<float>(v, u);
      if (z_now <= 0.0f) continue;
      // Parallax between the two viewing rays of X (Fig. 5).
      const Eigen::Vector3d a = (X - kf_centre).normalized(), b = (X - centre).normalized();
      if (a.dot(b) < cos_limit) {
        ++r.parallax_skipped;
        continue;
      }
      ++r.judged;
      const double threshold = params_.depth_threshold + params_.depth_threshold_slope * z_proj;
      if (z_proj - z_now <= threshold) continue;
      // The patch must agree: a lone closer pixel is noise or an edge, not an object.
      int valid = 0, closer = 0;
      for (int dv = -n; dv <= n; ++dv)
        for (int du = -n; du <= n; ++du) {
          const float d = depth.at<float>(v + dv, u + du);
          if (d <= 0.0f) continue;
          ++valid;
          closer += (z_proj - d > threshold) ? 1 : 0;
        }
      if (valid == 0 || closer < params_.neighbourhood_agreement * valid) continue;
      seeds.push_back({static_cast<float>(u), static_cast<float>(v), z_now});
    }
  }
  r.seeds = static_cast<int>(seeds.size());
  if (r.seeds < params_.min_seeds) return r;

  RegionGrowParams grow;
  grow.step = params_.grow_step;
  grow.band = params_.grow_band;
  grow.extent = params_.grow_extent;
  r.mask = grow_regions(depth, seeds, cam.fx, cam.fy, grow);
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const cv::Point2f& p = frame.keypoints()[i].pt;
    const int u = std::clamp(static_cast<int>(std::lround(p.x)), 0, r.mask.cols - 1);
    const int v = std::clamp(static_cast<int>(std::lround(p.y)), 0, r.mask.rows - 1);
    if (r.mask.at<std::uint8_t>(v, u) != 0) {
      r.dynamic[i] = true;
      ++r.flagged_keypoints;
    }
  }
  return r;
}

}  // namespace lrd::dynamic
