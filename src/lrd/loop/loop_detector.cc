#include "lrd/loop/loop_detector.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "lrd/loop/rigid_transform_ransac.h"
#include "lrd/map/keyframe.h"
#include "lrd/map/keyframe_database.h"
#include "lrd/map/map_point.h"
#include "lrd/match/bow_matcher.h"
#include "lrd/match/orb_matcher.h"
#include "lrd/optim/pose_optimizer.h"
#include "lrd/place/vocabulary.h"

namespace lrd::loop {

namespace {
// Projection radius (x scale) for a suggested loop's first search: the camera moved while
// tracking was lost, so the guess is a few centimetres and a degree or two off.
constexpr float kSuggestedRadius = 20.0f;

// The map points of `kf` and its covisible neighbours, each once, by id.
std::vector<map::MapPoint*> neighbourhood_points(map::KeyFrame& kf) {
  std::vector<map::KeyFrame*> kfs = kf.ordered_covisibles();
  kfs.push_back(&kf);
  std::sort(kfs.begin(), kfs.end(), map::ById{});
  std::vector<map::MapPoint*> points;
  for (map::KeyFrame* k : kfs) {
    if (k->is_bad()) continue;
    for (map::MapPoint* mp : k->map_points())
      if (mp != nullptr && !mp->is_bad()) points.push_back(mp);
  }
  std::sort(points.begin(), points.end(), map::ById{});
  points.erase(std::unique(points.begin(), points.end()), points.end());
  return points;
}

// Motion-only BA of `kf` against `matches` (per keypoint) from `T_cw`; outliers leave `matches`.
optim::PoseOptimizationResult refine_pose(const map::KeyFrame& kf, const Eigen::Isometry3d& T_cw,
                                          std::vector<map::MapPoint*>& matches) {
  optim::PoseOptimizationResult result = optim::optimize_frame_pose(kf.features(), matches, T_cw);
  for (std::size_t i = 0; i < result.outlier.size(); ++i)
    if (result.outlier[i]) matches[i] = nullptr;
  return result;
}
}  // namespace

LoopDetector::LoopDetector(map::KeyFrameDatabase& database, LoopDetectorParams params)
    : database_(database), params_(params) {}

void LoopDetector::loop_closed(const map::KeyFrame* kf) {
  last_loop_kf_ = kf->id();
  any_loop_ = true;
  groups_.clear();
}

bool LoopDetector::closed_since(const map::KeyFrame* kf) const {
  return any_loop_ && last_loop_kf_ >= kf->id();
}

std::optional<LoopDetection> LoopDetector::detect(map::KeyFrame* kf) {
  if (kf->is_bad() || kf->bow().empty()) return std::nullopt;
  if (any_loop_ && kf->id() < last_loop_kf_ + static_cast<std::uint64_t>(params_.min_keyframes_between))
    return std::nullopt;
  // The lowest similarity to the keyframe's own covisible neighbours: a loop candidate must look
  // at least as much like it as the views it was taken among.
  const auto neighbours = kf->ordered_covisibles();
  if (neighbours.empty()) return std::nullopt;
  double min_score = 1.0;
  for (const map::KeyFrame* n : neighbours) {
    if (n->is_bad() || n->bow().empty()) continue;
    min_score = std::min(min_score, place::Vocabulary::score(kf->bow(), n->bow()));
  }
  const auto candidates = database_.loop_candidates(kf, min_score);
  const auto consistent = consistent_candidates(candidates);
  for (map::KeyFrame* candidate : consistent) {
    auto detection = verify(kf, candidate);
    if (detection) return detection;
  }
  return std::nullopt;
}

std::vector<map::KeyFrame*> LoopDetector::consistent_candidates(
    const std::vector<map::KeyFrame*>& candidates) {
  std::vector<ConsistentGroup> current;
  std::vector<map::KeyFrame*> enough;
  std::vector<bool> previous_extended(groups_.size(), false);
  for (map::KeyFrame* candidate : candidates) {
    ConsistentGroup group;
    group.keyframes.insert(candidate->id());
    for (map::KeyFrame* n : candidate->ordered_covisibles()) group.keyframes.insert(n->id());
    bool consistent_for_some = false, enough_for_candidate = false;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      const bool shares = std::any_of(group.keyframes.begin(), group.keyframes.end(),
                                      [&](std::uint64_t k) { return groups_[g].keyframes.count(k) != 0; });
      if (!shares) continue;
      consistent_for_some = true;
      const int consistency = groups_[g].consistency + 1;
      if (!previous_extended[g]) {
        current.push_back({group.keyframes, consistency});
        previous_extended[g] = true;
      }
      if (consistency >= params_.consistency && !enough_for_candidate) {
        enough.push_back(candidate);
        enough_for_candidate = true;
      }
    }
    if (!consistent_for_some) current.push_back({group.keyframes, 0});
  }
  groups_ = std::move(current);
  return enough;
}

std::optional<LoopDetection> LoopDetector::verify(map::KeyFrame* kf, map::KeyFrame* candidate) const {
  if (candidate->is_bad()) return std::nullopt;
  std::vector<map::MapPoint*> bow_matches;
  const match::BowMatcher bow_matcher({0.75f, true});
  const int n_bow = bow_matcher.match(*kf, *candidate, bow_matches);
  if (n_bow < params_.min_bow_matches) return std::nullopt;

  const data::Frame& f1 = kf->features();
  const data::Frame& f2 = candidate->features();
  std::vector<PointCorrespondence> corr;
  std::vector<std::size_t> corr_index;
  for (std::size_t i = 0; i < bow_matches.size(); ++i) {
    map::MapPoint* mp2 = bow_matches[i];
    map::MapPoint* mp1 = kf->map_point(i);
    if (mp2 == nullptr || mp1 == nullptr || mp1->is_bad() || mp2->is_bad()) continue;
    const auto j = mp2->index_in(candidate);
    if (!j) continue;
    const cv::KeyPoint& k1 = f1.undistorted()[i];
    const cv::KeyPoint& k2 = f2.undistorted()[*j];
    corr.push_back({kf->T_cw() * mp1->position(), candidate->T_cw() * mp2->position(),
                    Eigen::Vector2d(k1.pt.x, k1.pt.y), Eigen::Vector2d(k2.pt.x, k2.pt.y),
                    f1.level_sigma2()[static_cast<std::size_t>(k1.octave)],
                    f2.level_sigma2()[static_cast<std::size_t>(k2.octave)]});
    corr_index.push_back(i);
  }
  RigidRansacParams rp;
  rp.iterations = params_.ransac_iterations;
  rp.min_inliers = params_.min_ransac_inliers;
  const RigidRansacResult ransac = estimate_rigid_ransac(corr, f1.camera(), rp);
  spdlog::debug("loop check keyframe {} - {}: {} BoW matches, {} RANSAC inliers", kf->id(), candidate->id(),
                n_bow, ransac.inliers);
  if (!ransac.ok) return std::nullopt;

  LoopDetection d;
  d.current = kf;
  d.loop = candidate;
  d.ransac_inliers = ransac.inliers;
  // T_12 takes the candidate's camera frame to the current one: in the candidate's map, the
  // current keyframe sits at T_12 * T_cw(candidate).
  d.T_cw_corrected = geometry::orthonormalized(ransac.T_12 * candidate->T_cw());
  d.matches.assign(kf->size(), nullptr);
  for (std::size_t c = 0; c < corr.size(); ++c)
    if (ransac.inlier[c]) d.matches[corr_index[c]] = bow_matches[corr_index[c]];
  // The loop side's neighbourhood, projected at the corrected pose for more matches.
  d.loop_points = neighbourhood_points(*candidate);
  const match::OrbMatcher projector({0.75f, false});
  projector.search_by_projection(*kf, d.T_cw_corrected, d.loop_points, d.matches, 10.0f);
  d.match_count = static_cast<int>(
      std::count_if(d.matches.begin(), d.matches.end(), [](auto* p) { return p != nullptr; }));
  spdlog::debug("loop check keyframe {} - {}: {} matches after projection", kf->id(), candidate->id(),
                d.match_count);
  if (d.match_count < params_.min_matches) return std::nullopt;
  return d;
}

std::optional<LoopDetection> LoopDetector::verify_suggested(map::KeyFrame* kf, map::KeyFrame* candidate,
                                                            const Eigen::Isometry3d& T_cw_guess) const {
  if (kf->is_bad() || candidate->is_bad() || kf == candidate) return std::nullopt;
  LoopDetection d;
  d.current = kf;
  d.loop = candidate;
  d.loop_points = neighbourhood_points(*candidate);
  d.matches.assign(kf->size(), nullptr);
  const match::OrbMatcher projector({0.75f, false});
  projector.search_by_projection(*kf, T_cw_guess, d.loop_points, d.matches, kSuggestedRadius);
  const optim::PoseOptimizationResult first = refine_pose(*kf, T_cw_guess, d.matches);
  d.ransac_inliers = first.inliers;
  spdlog::debug("suggested loop keyframe {} - {}: {} inliers at the guess", kf->id(), candidate->id(),
                first.inliers);
  if (first.inliers < params_.min_ransac_inliers) return std::nullopt;
  projector.search_by_projection(*kf, first.T_cw, d.loop_points, d.matches, 10.0f);
  const optim::PoseOptimizationResult second = refine_pose(*kf, first.T_cw, d.matches);
  d.match_count = second.inliers;
  d.T_cw_corrected = geometry::orthonormalized(second.T_cw);
  spdlog::debug("suggested loop keyframe {} - {}: {} inliers after projection", kf->id(), candidate->id(),
                d.match_count);
  if (d.match_count < params_.min_matches) return std::nullopt;
  return d;
}

}  // namespace lrd::loop
