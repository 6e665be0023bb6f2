#include "lrd/dynamic/dynamic_point_filter.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "lrd/data/frame.h"
#include "lrd/dynamic/depth_region_grower.h"
#include "lrd/dynamic/mask_propagator.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"

namespace lrd::dynamic {

namespace {
// Raw (distorted) pixel of an ideal one: depth images are registered to the raw colour image,
// so depth is read there (Brown-Conrady, OpenCV's k1 k2 p1 p2 k3).
Eigen::Vector2d distort(const camera::PinholeCamera& cam, const Eigen::Vector2d& ideal) {
  const camera::Distortion& d = cam.distortion;
  if (d.is_zero()) return ideal;
  const double x = (ideal.x() - cam.cx) / cam.fx, y = (ideal.y() - cam.cy) / cam.fy;
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  const double xd = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
  const double yd = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
  return {cam.fx * xd + cam.cx, cam.fy * yd + cam.cy};
}

// A keyframe point carried into the current frame, before the frame's depth is read there.
struct Projection {
  Eigen::Vector3d X;     // world
  double z;              // depth in the current camera
  int u, v;              // raw (distorted) pixel, `margin` or more inside the image
  std::size_t keyframe;  // index into the keyframes compared
};

// Where the keyframes' points landed in the frame, by 16-pixel cell: what the map knows to be
// static surface there, and at what depth.
class KnownSurfaces {
 public:
  KnownSurfaces(const std::vector<Projection>& points, cv::Size size)
      : cols_(size.width / kCell + 1), rows_(size.height / kCell + 1), first_(cell_count() + 1, 0) {
    // Counting sort by cell: one allocation, points of a cell contiguous.
    for (const Projection& p : points) ++first_[cell(p.u, p.v) + 1];
    for (std::size_t c = 1; c < first_.size(); ++c) first_[c] += first_[c - 1];
    entries_.resize(points.size());
    std::vector<std::size_t> next(first_.begin(), first_.end() - 1);
    for (const Projection& p : points) entries_[next[cell(p.u, p.v)]++] = {p.u, p.v, static_cast<float>(p.z)};
  }
  // Whether a point of the map lands within `radius` pixels of (u, v) at a depth within
  // `tolerance` of `z`.
  [[nodiscard]] bool near(int u, int v, float z, float tolerance, int radius) const {
    const int cx0 = std::max(0, (u - radius) / kCell), cx1 = std::min(cols_ - 1, (u + radius) / kCell);
    const int cy0 = std::max(0, (v - radius) / kCell), cy1 = std::min(rows_ - 1, (v + radius) / kCell);
    for (int cy = cy0; cy <= cy1; ++cy)
      for (int cx = cx0; cx <= cx1; ++cx) {
        const auto c = static_cast<std::size_t>(cy * cols_ + cx);
        for (std::size_t k = first_[c]; k < first_[c + 1]; ++k) {
          const Entry& e = entries_[k];
          if (std::abs(e.u - u) <= radius && std::abs(e.v - v) <= radius && std::abs(e.z - z) <= tolerance)
            return true;
        }
      }
    return false;
  }

 private:
  static constexpr int kCell = 16;
  struct Entry {
    int u, v;
    float z;
  };
  [[nodiscard]] std::size_t cell_count() const { return static_cast<std::size_t>(cols_ * rows_); }
  [[nodiscard]] std::size_t cell(int u, int v) const {
    return static_cast<std::size_t>((v / kCell) * cols_ + u / kCell);
  }
  int cols_, rows_;
  std::vector<std::size_t> first_;
  std::vector<Entry> entries_;
};

// The keyframe's points with depth that land in the frame within the depth range. Pure arithmetic,
// kept apart from the depth reads so that those can be fetched ahead (below).
void project_points(const map::KeyFrame& kf, std::size_t index, const Eigen::Isometry3d& T_cw,
                    const camera::PinholeCamera& cam, cv::Size size, double max_depth, int margin,
                    std::vector<Projection>& out) {
  const data::Frame& f = kf.features();
  const Eigen::Isometry3d T_w_kf = kf.T_wc();
  for (std::size_t i = 0; i < f.size(); ++i) {
    const float z_kf = f.depth(i);
    if (z_kf <= 0.0f || z_kf > max_depth) continue;
    const cv::Point2f& p = f.undistorted()[i].pt;
    const Eigen::Vector3d X = T_w_kf * cam.unproject(p.x, p.y, z_kf);
    const Eigen::Vector3d Xc = T_cw * X;
    const double z_proj = Xc.z();
    if (z_proj <= 0.1 || z_proj > max_depth) continue;
    const Eigen::Vector2d uv = distort(cam, cam.project(Xc));
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    if (u < margin || v < margin || u >= size.width - margin || v >= size.height - margin) continue;
    out.push_back({X, z_proj, u, v, index});
  }
}
}  // namespace

bool flags_most_pose_matches(const data::Frame& frame, const std::vector<bool>& dynamic) {
  constexpr std::size_t kMinMatches = 30;
  constexpr double kMostShare = 0.5;
  std::size_t matched = 0, flagged = 0;
  for (std::size_t i = 0; i < frame.size() && i < dynamic.size(); ++i) {
    if (frame.map_points[i] == nullptr || frame.outliers[i]) continue;
    ++matched;
    flagged += dynamic[i] ? 1 : 0;
  }
  return matched >= kMinMatches && static_cast<double>(flagged) > kMostShare * static_cast<double>(matched);
}

std::vector<map::KeyFrame*> DynamicPointFilter::select_keyframes(
    const Eigen::Isometry3d& T_cw, double timestamp, const std::vector<map::KeyFrame*>& candidates) const {
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

std::optional<Eigen::Isometry3d> DynamicPointFilter::robust_pose(const data::Frame& frame,
                                                                 int* inliers) const {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const map::MapPoint* mp = frame.map_points[i];
    if (mp == nullptr || mp->is_bad()) continue;
    const Eigen::Vector3d& X = mp->position();
    object.emplace_back(X.x(), X.y(), X.z());
    image.emplace_back(frame.undistorted()[i].pt.x, frame.undistorted()[i].pt.y);
  }
  if (inliers != nullptr) *inliers = 0;
  if (object.size() < 20) return std::nullopt;
  const camera::PinholeCamera& cam = frame.camera();
  const cv::Matx33d K(cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  const Eigen::Isometry3d& T = frame.T_cw();
  cv::Mat R, rvec, tvec;
  cv::eigen2cv(Eigen::Matrix3d(T.linear()), R);
  cv::Rodrigues(R, rvec);
  cv::eigen2cv(Eigen::Vector3d(T.translation()), tvec);
  std::vector<int> kept;
  const bool ok = cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, true, 200, 2.5f, 0.999,
                                     kept, cv::SOLVEPNP_ITERATIVE);
  if (inliers != nullptr) *inliers = static_cast<int>(kept.size());
  if (!ok || kept.size() < std::max<std::size_t>(15, object.size() / 3)) return std::nullopt;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  Eigen::Vector3d te;
  cv::cv2eigen(R, Re);
  cv::cv2eigen(tvec, te);
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Re;
  out.translation() = te;
  // It corrects a drag of centimetres; a jump far from the tracker's estimate is a degenerate
  // sample (seen once in ~1000 frames, which then lost tracking), not a better pose.
  const Eigen::Isometry3d delta = out * T.inverse();
  if (delta.translation().norm() > 0.1 ||
      Eigen::AngleAxisd(delta.linear()).angle() > 5.0 * std::numbers::pi / 180.0)
    return std::nullopt;
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
  constexpr int kCell = 24;  // pixels
  const int cells_x = depth.cols / kCell + 1, cells_y = depth.rows / kCell + 1;
  std::vector<int> judged_in(static_cast<std::size_t>(cells_x * cells_y), 0), seeds_in(judged_in.size(), 0);
  auto cell_of = [&](int u, int v) { return static_cast<std::size_t>((v / kCell) * cells_x + u / kCell); };

  const auto keyframes = select_keyframes(T_cw, frame.timestamp(), candidates);
  r.keyframes = static_cast<int>(keyframes.size());
  std::vector<Projection> projected;
  std::vector<Eigen::Vector3d> kf_centres;
  std::size_t total = 0;
  for (const map::KeyFrame* kf : keyframes) total += kf->features().size();
  projected.reserve(total);  // one allocation a frame, not one per doubling
  for (const map::KeyFrame* kf : keyframes) {
    project_points(*kf, kf_centres.size(), T_cw, cam, depth.size(), params_.max_depth, n, projected);
    kf_centres.push_back(kf->camera_center());
  }
  const KnownSurfaces known(projected, depth.size());
  // Points read the depth image at scattered pixels: each one's rows are fetched a few points
  // ahead, as most reads otherwise missed the cache (a third of the check's time).
  constexpr std::size_t kAhead = 8;
  for (std::size_t j = 0; j < projected.size(); ++j) {
    if (j + kAhead < projected.size()) {
      const Projection& next = projected[j + kAhead];
      for (int dv = -n; dv <= n; ++dv) __builtin_prefetch(depth.ptr<float>(next.v + dv) + next.u);
    }
    const auto& [X, z_proj, u, v, kf_index] = projected[j];
    const float z_now = depth.at<float>(v, u);
    if (z_now <= 0.0f) continue;
    // Parallax between the two viewing rays of X (Fig. 5).
    const Eigen::Vector3d a = (X - kf_centres[kf_index]).normalized(), b = (X - centre).normalized();
    if (a.dot(b) < cos_limit) {
      ++r.parallax_skipped;
      continue;
    }
    ++r.judged;
    ++judged_in[cell_of(u, v)];
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
    // The map knows a static surface at the depth now measured, right beside the pixel: the
    // camera moved and static foreground (a monitor's edge, a desk) now hides the point. Nothing
    // moved there; a moving object stands where the map has no points at its depth.
    if (params_.known_surface_px > 0 &&
        known.near(u, v, z_now,
                   static_cast<float>(params_.depth_threshold + params_.depth_threshold_slope * z_now),
                   params_.known_surface_px))
      continue;
    seeds.push_back({static_cast<float>(u), static_cast<float>(v), z_now});
    ++seeds_in[cell_of(u, v)];
  }
  // A moving object makes most judged points around it closer than expected; plain occlusion at
  // a depth edge (a wall point now hidden by a desk seen from a new angle) makes a few. Seeds
  // count only where they are the majority of the judged points of their 3x3-cell neighbourhood.
  {
    std::vector<RegionSeed> supported;
    for (const RegionSeed& seed : seeds) {
      const int cx = static_cast<int>(seed.u) / kCell, cy = static_cast<int>(seed.v) / kCell;
      int judged = 0, moving = 0;
      for (int y = std::max(0, cy - 1); y <= std::min(cells_y - 1, cy + 1); ++y)
        for (int x = std::max(0, cx - 1); x <= std::min(cells_x - 1, cx + 1); ++x) {
          judged += judged_in[static_cast<std::size_t>(y * cells_x + x)];
          moving += seeds_in[static_cast<std::size_t>(y * cells_x + x)];
        }
      if (moving < params_.min_seeds || moving < params_.seed_support * judged) continue;
      // A seed on an object the segmentation already masked adds nothing, and grown from there the
      // region leaks into what the object touches: a seated person into the chair and the desk.
      if (frame.dynamic_mask.size() == depth.size() &&
          frame.dynamic_mask.at<std::uint8_t>(static_cast<int>(seed.v), static_cast<int>(seed.u)) != 0)
        continue;
      supported.push_back(seed);
    }
    seeds.swap(supported);
  }
  r.seeds = static_cast<int>(seeds.size());
  if (r.seeds < params_.min_seeds) return r;

  RegionGrowParams grow;
  grow.step = params_.grow_step;
  grow.band = params_.grow_band;
  grow.extent = params_.grow_extent;
  r.mask = dilated_mask(grow_regions(depth, seeds, cam.fx, cam.fy, grow), params_.region_dilation_px);
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
