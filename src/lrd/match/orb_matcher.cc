#include "lrd/match/orb_matcher.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "lrd/features/descriptor_distance.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/map_point.h"
#include "lrd/match/frustum.h"
#include "lrd/match/rotation_histogram.h"

namespace lrd::match {

using features::descriptor_distance;

namespace {

bool already_matched(const data::Frame& f, std::size_t i) {
  const map::MapPoint* mp = f.map_points[i];
  return mp != nullptr && mp->num_observations() > 0;
}

}  // namespace

int OrbMatcher::search_by_projection(data::Frame& current, const data::Frame& last, float th) const {
  const camera::PinholeCamera& cam = current.camera();
  const Eigen::Isometry3d& T_cw = current.T_cw();
  // Current camera centre in the last frame: moving forward, points appear at finer levels
  // than they were seen; moving backward, at coarser ones.
  const Eigen::Vector3d t_lc = last.T_cw() * current.T_wc().translation();
  const double baseline = cam.baseline();
  const bool forward = t_lc.z() > baseline, backward = -t_lc.z() > baseline;

  RotationHistogram hist;
  int matches = 0;
  std::vector<std::size_t> cands;
  for (std::size_t i = 0; i < last.size(); ++i) {
    map::MapPoint* mp = last.map_points[i];
    if (mp == nullptr || last.outliers[i] || mp->is_bad()) continue;
    const Eigen::Vector3d pc = T_cw * mp->position();
    if (pc.z() <= 0.0) continue;
    const Eigen::Vector2d uv = cam.project(pc);
    if (!current.in_bounds(uv.x(), uv.y())) continue;
    const int octave = last.undistorted()[i].octave;
    const float radius = th * current.scale_factors()[static_cast<std::size_t>(octave)];
    if (forward)
      current.features_in_area(uv.x(), uv.y(), radius, octave, -1, cands);
    else if (backward)
      current.features_in_area(uv.x(), uv.y(), radius, 0, octave, cands);
    else
      current.features_in_area(uv.x(), uv.y(), radius, std::max(0, octave - 1), octave + 1, cands);
    if (cands.empty()) continue;
    const double u_right = uv.x() - cam.bf / pc.z();
    int best = 256;
    std::size_t best_idx = 0;
    for (const std::size_t j : cands) {
      if (already_matched(current, j)) continue;
      if (current.u_right(j) > 0.0f && std::abs(u_right - current.u_right(j)) > radius) continue;
      const int d = descriptor_distance(mp->descriptor(), current.descriptors().row(static_cast<int>(j)));
      if (d < best) {
        best = d;
        best_idx = j;
      }
    }
    if (best > kThHigh) continue;
    current.map_points[best_idx] = mp;
    current.outliers[best_idx] = false;
    ++matches;
    if (params_.check_orientation)
      hist.add(last.undistorted()[i].angle, current.undistorted()[best_idx].angle, best_idx);
  }
  if (params_.check_orientation) {
    for (const std::size_t j : hist.rejected()) {
      current.map_points[j] = nullptr;
      --matches;
    }
  }
  return matches;
}

int OrbMatcher::search_by_projection(data::Frame& current, const std::vector<map::MapPoint*>& points,
                                     float th) const {
  int matches = 0;
  std::vector<std::size_t> cands;
  for (map::MapPoint* mp : points) {
    if (!mp->track.in_view || mp->is_bad()) continue;
    const int level = mp->track.scale_level;
    const float scale = current.scale_factors()[static_cast<std::size_t>(level)];
    // A wider window when the viewing angle differs (ORB-SLAM2's RadiusByViewingCos).
    const float radius = (mp->track.view_cos > 0.998f ? 2.5f : 4.0f) * th * scale;
    current.features_in_area(mp->track.proj_x, mp->track.proj_y, radius, level - 1, level, cands);
    if (cands.empty()) continue;
    int best = 256, second = 256, best_level = -1, second_level = -1;
    std::size_t best_idx = 0;
    for (const std::size_t j : cands) {
      if (already_matched(current, j)) continue;
      if (current.u_right(j) > 0.0f && std::abs(mp->track.proj_xr - current.u_right(j)) > radius) continue;
      const int d = descriptor_distance(mp->descriptor(), current.descriptors().row(static_cast<int>(j)));
      const int lvl = current.undistorted()[j].octave;
      if (d < best) {
        second = best, second_level = best_level;
        best = d, best_level = lvl, best_idx = j;
      } else if (d < second) {
        second = d, second_level = lvl;
      }
    }
    if (best > kThHigh) continue;
    if (best_level == second_level &&
        static_cast<float>(best) > params_.nn_ratio * static_cast<float>(second))
      continue;
    current.map_points[best_idx] = mp;
    current.outliers[best_idx] = false;
    ++matches;
  }
  return matches;
}

int OrbMatcher::search_by_projection(const map::KeyFrame& kf, const Eigen::Isometry3d& T_cw,
                                     const std::vector<map::MapPoint*>& points,
                                     std::vector<map::MapPoint*>& matched, float th) const {
  const data::Frame& f = kf.features();
  std::vector<map::MapPoint*> already;
  for (map::MapPoint* mp : matched)
    if (mp != nullptr) already.push_back(mp);
  std::sort(already.begin(), already.end());
  int found = 0;
  for (map::MapPoint* mp : points) {
    if (mp == nullptr || mp->is_bad() || std::binary_search(already.begin(), already.end(), mp)) continue;
    const auto seen = project_in_frustum(f, T_cw, *mp);
    if (!seen) continue;
    const Eigen::Vector2d& uv = seen->pixel;
    const int level = seen->level;
    const float radius = th * f.scale_factors()[static_cast<std::size_t>(level)];
    int best = 256;
    std::size_t best_idx = SIZE_MAX;
    for (const std::size_t j : f.features_in_area(uv.x(), uv.y(), radius)) {
      if (matched[j] != nullptr) continue;
      const int kp_level = f.undistorted()[j].octave;
      if (kp_level < level - 1 || kp_level > level) continue;
      const int d = descriptor_distance(mp->descriptor(), f.descriptors().row(static_cast<int>(j)));
      if (d < best) {
        best = d;
        best_idx = j;
      }
    }
    if (best_idx == SIZE_MAX || best > kThLow) continue;
    matched[best_idx] = mp;
    ++found;
  }
  return found;
}

int OrbMatcher::search_by_descriptor(const map::KeyFrame& kf, data::Frame& current) const {
  const data::Frame& kff = kf.features();
  const std::size_t n = current.size();
  std::vector<int> best_for(n, std::numeric_limits<int>::max());
  std::vector<std::size_t> source(n, SIZE_MAX);
  for (std::size_t i = 0; i < kf.size(); ++i) {
    map::MapPoint* mp = kf.map_point(i);
    if (mp == nullptr || mp->is_bad()) continue;
    const std::uint8_t* d_kf = kff.descriptors().ptr(static_cast<int>(i));
    int best = 256, second = 256;
    std::size_t best_idx = 0;
    for (std::size_t j = 0; j < n; ++j) {
      const int d = descriptor_distance(d_kf, current.descriptors().ptr(static_cast<int>(j)));
      if (d < best) {
        second = best;
        best = d, best_idx = j;
      } else if (d < second) {
        second = d;
      }
    }
    if (best > kThLow || static_cast<float>(best) >= params_.nn_ratio * static_cast<float>(second)) continue;
    // One keyframe point per keypoint: the closer descriptor wins.
    if (best < best_for[best_idx]) {
      best_for[best_idx] = best;
      source[best_idx] = i;
    }
  }
  RotationHistogram hist;
  int matches = 0;
  for (std::size_t j = 0; j < n; ++j) {
    if (source[j] == SIZE_MAX) continue;
    current.map_points[j] = kf.map_point(source[j]);
    current.outliers[j] = false;
    ++matches;
    if (params_.check_orientation)
      hist.add(kff.undistorted()[source[j]].angle, current.undistorted()[j].angle, j);
  }
  if (params_.check_orientation) {
    for (const std::size_t j : hist.rejected()) {
      current.map_points[j] = nullptr;
      --matches;
    }
  }
  return matches;
}

std::vector<std::pair<std::size_t, std::size_t>> OrbMatcher::search_for_triangulation(
    map::KeyFrame& kf1, map::KeyFrame& kf2, const Eigen::Matrix3d& F12) const {
  const data::Frame& f1 = kf1.features();
  const data::Frame& f2 = kf2.features();
  const camera::PinholeCamera& cam = f1.camera();
  // Epipole: kf1's centre seen in kf2.
  const Eigen::Vector3d c = kf2.T_cw() * kf1.camera_center();
  const double ex = cam.fx * c.x() / c.z() + cam.cx, ey = cam.fy * c.y() / c.z() + cam.cy;

  std::vector<std::size_t> free2;
  for (std::size_t j = 0; j < kf2.size(); ++j)
    if (kf2.map_point(j) == nullptr) free2.push_back(j);
  std::vector<bool> used2(kf2.size(), false);

  RotationHistogram hist;
  std::vector<std::pair<std::size_t, std::size_t>> matches;
  for (std::size_t i = 0; i < kf1.size(); ++i) {
    if (kf1.map_point(i) != nullptr) continue;
    const bool stereo1 = f1.u_right(i) >= 0.0f;
    const cv::KeyPoint& kp1 = f1.undistorted()[i];
    const std::uint8_t* d1 = f1.descriptors().ptr(static_cast<int>(i));
    // Epipolar line in kf2 of kp1: l = x1' F12.
    const double a = kp1.pt.x * F12(0, 0) + kp1.pt.y * F12(1, 0) + F12(2, 0);
    const double b = kp1.pt.x * F12(0, 1) + kp1.pt.y * F12(1, 1) + F12(2, 1);
    const double cc = kp1.pt.x * F12(0, 2) + kp1.pt.y * F12(1, 2) + F12(2, 2);
    const double den = a * a + b * b;
    if (den == 0.0) continue;
    int best = kThLow + 1;
    std::size_t best_idx = SIZE_MAX;
    for (const std::size_t j : free2) {
      if (used2[j]) continue;
      const int d = descriptor_distance(d1, f2.descriptors().ptr(static_cast<int>(j)));
      if (d > kThLow || d >= best) continue;
      const cv::KeyPoint& kp2 = f2.undistorted()[j];
      const bool stereo2 = f2.u_right(j) >= 0.0f;
      if (!stereo1 && !stereo2) {
        // Too close to the epipole: depth is ill-conditioned there.
        const double dx = ex - kp2.pt.x, dy = ey - kp2.pt.y;
        if (dx * dx + dy * dy < 100.0 * f2.scale_factors()[static_cast<std::size_t>(kp2.octave)]) continue;
      }
      const double num = a * kp2.pt.x + b * kp2.pt.y + cc;
      if (num * num / den >= 3.84 * f2.level_sigma2()[static_cast<std::size_t>(kp2.octave)]) continue;
      best = d;
      best_idx = j;
    }
    if (best_idx == SIZE_MAX) continue;
    used2[best_idx] = true;
    if (params_.check_orientation) hist.add(kp1.angle, f2.undistorted()[best_idx].angle, matches.size());
    matches.emplace_back(i, best_idx);
  }
  if (params_.check_orientation) {
    std::vector<bool> drop(matches.size(), false);
    for (const std::size_t k : hist.rejected()) drop[k] = true;
    std::vector<std::pair<std::size_t, std::size_t>> kept;
    for (std::size_t k = 0; k < matches.size(); ++k)
      if (!drop[k]) kept.push_back(matches[k]);
    matches.swap(kept);
  }
  return matches;
}

int OrbMatcher::fuse(map::KeyFrame& kf, const std::vector<map::MapPoint*>& points, float th) const {
  const data::Frame& f = kf.features();
  const camera::PinholeCamera& cam = f.camera();
  const Eigen::Isometry3d T_cw = kf.T_cw();
  int fused = 0;
  for (map::MapPoint* mp : points) {
    if (mp == nullptr || mp->is_bad() || mp->is_in_keyframe(&kf)) continue;
    const auto seen = project_in_frustum(f, T_cw, *mp);  // viewing angle up to 60 degrees
    if (!seen) continue;
    const Eigen::Vector3d& pc = seen->point_camera;
    const Eigen::Vector2d& uv = seen->pixel;
    const int level = seen->level;
    const float radius = th * f.scale_factors()[static_cast<std::size_t>(level)];
    int best = 256;
    std::size_t best_idx = 0;
    for (const std::size_t j : f.features_in_area(uv.x(), uv.y(), radius)) {
      const cv::KeyPoint& kp = f.undistorted()[j];
      if (kp.octave < level - 1 || kp.octave > level) continue;
      const double inv_s2 = f.inv_level_sigma2()[static_cast<std::size_t>(kp.octave)];
      const double chi2_max = f.u_right(j) >= 0.0f ? 7.8 : 5.99;
      if (cam.reprojection_chi2(pc, kp.pt.x, kp.pt.y, f.u_right(j), inv_s2) > chi2_max) continue;
      const int d = descriptor_distance(mp->descriptor(), f.descriptors().row(static_cast<int>(j)));
      if (d < best) {
        best = d;
        best_idx = j;
      }
    }
    if (best > kThLow) continue;
    map::MapPoint* existing = kf.map_point(best_idx);
    if (existing != nullptr) {
      if (!existing->is_bad()) {
        if (existing->num_observations() > mp->num_observations())
          mp->replace(existing);
        else
          existing->replace(mp);
      }
    } else {
      mp->add_observation(&kf, best_idx);
      kf.add_map_point(mp, best_idx);
    }
    ++fused;
  }
  return fused;
}

}  // namespace lrd::match
