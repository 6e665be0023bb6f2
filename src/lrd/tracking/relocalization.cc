// Tracker::relocalize (ORB-SLAM2's Relocalization, paper §2.2): when tracking is lost, the frame's
// bag of words finds keyframes of the same place; their map points are matched through the
// vocabulary, a pose is found by PnP with RANSAC and refined by motion-only BA. Local-map tracking
// then confirms it (tracking requires more inliers than usual right after a recovery).
#include <spdlog/spdlog.h>

#include <opencv2/calib3d.hpp>
#include <optional>
#include <unordered_set>
#include <utility>

#include "lrd/map/keyframe.h"
#include "lrd/map/keyframe_database.h"
#include "lrd/map/map_point.h"
#include "lrd/match/bow_matcher.h"
#include "lrd/match/frustum.h"
#include "lrd/tracking/tracker.h"

namespace lrd::tracking {

namespace {
constexpr int kMinBowMatches = 15;  // ORB-SLAM2: candidates with fewer matches are discarded
constexpr int kMinPnpInliers = 12;
constexpr std::size_t kMaxCandidates = 10;
constexpr int kMinGuidedStart = 10;  // ORB-SLAM2: fewer BA inliers than this, the candidate is dropped
constexpr int kGuidedTarget = 50;    // ... fewer than this, it looks for more matches by projection

// ORB-SLAM2's guided search after a weak PnP pose: the candidate keyframe's map points not yet
// matched, projected into the frame at that pose and matched within th * scale pixels. A view
// that overlaps the map only in part (a loaded map seen from its edge) gains the matches that
// bag-of-words matching, restricted to the same vocabulary nodes, missed. Returns the matches
// added.
int guided_matches(data::Frame& frame, const map::KeyFrame& kf, const match::OrbMatcher& matcher, float th) {
  std::unordered_set<const map::MapPoint*> matched(frame.map_points.begin(), frame.map_points.end());
  std::vector<map::MapPoint*> points;
  for (map::MapPoint* mp : kf.map_points()) {
    if (mp == nullptr || mp->is_bad() || matched.count(mp) != 0) continue;
    if (match::mark_for_projection_search(frame, *mp)) points.push_back(mp);
  }
  return matcher.search_by_projection(frame, points, th);
}
}  // namespace

bool Tracker::relocalize(data::Frame& frame) {
  if (vocabulary_ == nullptr || database_ == nullptr) return false;
  frame.compute_bow(*vocabulary_);
  const std::vector<map::KeyFrame*> candidates = database_->relocalization_candidates(frame);
  const match::BowMatcher matcher({0.75f, true});
  const camera::PinholeCamera& cam = frame.camera();
  const cv::Matx33d K(cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  std::vector<map::MapPoint*> matches;
  // The first pose found beyond where the camera can have gone since it was lost: taken only when
  // no candidate gives a nearer one (a map that drifted holds the same place twice).
  struct Found {
    map::KeyFrame* kf;
    int inliers;
    double metres;  // from the last tracked pose
    Eigen::Isometry3d T_cw;
    std::vector<map::MapPoint*> map_points;
  };
  std::optional<Found> far;
  for (std::size_t c = 0; c < candidates.size() && c < kMaxCandidates; ++c) {
    map::KeyFrame* kf = candidates[c];
    if (kf->is_bad()) continue;
    if (matcher.match(*kf, frame, matches) < kMinBowMatches) continue;
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    std::vector<std::size_t> index;
    for (std::size_t i = 0; i < matches.size(); ++i) {
      if (matches[i] == nullptr) continue;
      const Eigen::Vector3d& x = matches[i]->position();
      object.emplace_back(x.x(), x.y(), x.z());
      image.emplace_back(frame.undistorted()[i].pt.x, frame.undistorted()[i].pt.y);
      index.push_back(i);
    }
    // OpenCV's RANSAC draws from a fixed seed: relocalization stays deterministic.
    cv::Mat rvec, tvec;
    std::vector<int> inliers;
    if (!cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false, 300, 4.0f, 0.99, inliers,
                            cv::SOLVEPNP_EPNP) ||
        static_cast<int>(inliers.size()) < kMinPnpInliers)
      continue;
    cv::Matx33d R;
    cv::Rodrigues(rvec, R);
    Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) T_cw.linear()(r, k) = R(r, k);
      T_cw.translation()(r) = tvec.at<double>(r);
    }
    std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
    std::fill(frame.outliers.begin(), frame.outliers.end(), false);
    for (const int k : inliers)
      frame.map_points[index[static_cast<std::size_t>(k)]] = matches[index[static_cast<std::size_t>(k)]];
    frame.set_pose(T_cw);
    int good = optimize_pose(frame);
    spdlog::debug("frame {}: relocalization against keyframe {}: {} BoW matches, {} PnP inliers, {} after BA",
                  frame.id(), kf->id(), index.size(), inliers.size(), good);
    if (good >= kMinGuidedStart && good < kGuidedTarget) {
      for (std::size_t i = 0; i < frame.size(); ++i)
        if (frame.outliers[i]) frame.map_points[i] = nullptr;
      if (good + guided_matches(frame, *kf, local_map_.matcher(), 10.0f) >= kGuidedTarget) {
        good = optimize_pose(frame);
        spdlog::debug("frame {}: {} inliers after the guided search", frame.id(), good);
      }
    }
    if (good < params_.min_relocalization_inliers) continue;
    for (std::size_t i = 0; i < frame.size(); ++i)
      if (frame.outliers[i]) frame.map_points[i] = nullptr;
    if (const auto metres = implausible_recovery(frame)) {
      spdlog::debug("frame {}: relocalization against keyframe {} is {:.2f} m from the last tracked pose",
                    frame.id(), kf->id(), *metres);
      if (!far) far = Found{kf, good, *metres, frame.T_cw(), frame.map_points};
      continue;
    }
    reference_kf_ = kf;
    spdlog::info("frame {}: relocalized against keyframe {} ({} inliers)", frame.id(), kf->id(), good);
    return true;
  }
  std::fill(frame.outliers.begin(), frame.outliers.end(), false);
  if (!far) {
    std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
    return false;
  }
  frame.set_pose(far->T_cw);
  frame.map_points = std::move(far->map_points);
  reference_kf_ = far->kf;
  spdlog::debug("frame {}: relocalized against keyframe {} ({} inliers), {:.2f} m from the last tracked pose",
                frame.id(), far->kf->id(), far->inliers, far->metres);
  return true;
}

}  // namespace lrd::tracking
