// ORB matching on real extracted features of an exactly rendered textured plane: every search of
// the matcher finds many matches, and nearly all of them are geometrically right (the matched
// keypoint lies where the true pose projects the map point); the filters (map points not in view,
// outliers, keypoints already taken, epipolar distance, rotation consistency) do what they claim.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "lrd/geometry/triangulation.h"
#include "lrd/map/map.h"
#include "lrd/match/orb_matcher.h"
#include "lrd/match/rotation_histogram.h"
#include "textured_plane.h"

using lrd::data::Frame;
using lrd::map::KeyFrame;
using lrd::map::Map;
using lrd::map::MapPoint;
using lrd::match::MatcherParams;
using lrd::match::OrbMatcher;
using lrd::test::TexturedPlane;

namespace {

// "Geometrically right": the keypoint lies within 3 pixels of its own pyramid level (3 * scale at
// level 0) of the true projection of the map point. Map points come from keypoint positions and
// depth of the first view, so detection noise of both views is in there.
double tolerance(const Frame& f, std::size_t j) {
  return 3.0 * f.scale_factors()[static_cast<std::size_t>(f.undistorted()[j].octave)];
}

bool right(const TexturedPlane& scene, const Frame& f, std::size_t j, const Eigen::Isometry3d& T_true,
           const Eigen::Vector3d& x) {
  return scene.pixel_error(f, j, T_true, x) < tolerance(f, j);
}

struct Tally {
  int matches = 0;
  int correct = 0;
  [[nodiscard]] double ratio() const { return matches ? static_cast<double>(correct) / matches : 0.0; }
  [[nodiscard]] int wrong() const { return matches - correct; }
};

// The matches written into `current.map_points`, checked against the true pose of `current`;
// no map point may be matched twice.
Tally check_frame_matches(const TexturedPlane& scene, const Frame& current, const Eigen::Isometry3d& T_true) {
  Tally t;
  std::set<const MapPoint*> seen;
  for (std::size_t j = 0; j < current.size(); ++j) {
    const MapPoint* mp = current.map_points[j];
    if (mp == nullptr) continue;
    ++t.matches;
    EXPECT_TRUE(seen.insert(mp).second) << "map point matched twice";
    t.correct += right(scene, current, j, T_true, mp->position());
  }
  return t;
}

// View 0 becomes a keyframe with a map point per keypoint with depth, and the "last frame" of
// tracking with those matches; view 1 is the current frame, its pose set to the truth.
struct TwoViews {
  TexturedPlane scene;
  Map map;
  Eigen::Isometry3d T0, T1;
  KeyFrame* kf = nullptr;
  Frame last;
  Frame current;
  TwoViews(const Eigen::Isometry3d& T0_, const Eigen::Isometry3d& T1_)
      : T0(T0_), T1(T1_), last(scene.frame(0, T0)), current(scene.frame(1, T1)) {
    kf = lrd::test::keyframe_with_points(map, last);
    last.map_points = kf->map_points();
  }
};

const Eigen::Isometry3d kIdentity = Eigen::Isometry3d::Identity();

// As tracking's in_frustum for the keyframe's points seen from the current frame at its true
// pose: projection, virtual right coordinate, predicted level and viewing cosine. Points put in
// `hidden` (every third one, when given) are declared out of view. Returns the number in view.
int project_local_points(TwoViews& v, std::vector<MapPoint*>& points, std::set<const MapPoint*>* hidden) {
  const auto& cam = v.scene.camera();
  const auto& sf = v.current.scale_factors();
  int in_view = 0;
  for (MapPoint* mp : v.kf->map_points()) {
    if (mp == nullptr) continue;
    points.push_back(mp);
    const Eigen::Vector3d pc = v.T1 * mp->position();
    const Eigen::Vector2d uv = cam.project(pc);
    const Eigen::Vector3d po = mp->position() - v.current.T_wc().translation();
    const float dist = static_cast<float>(po.norm());
    const bool hide = hidden != nullptr && points.size() % 3 == 0;
    if (hide) hidden->insert(mp);
    mp->track.in_view = !hide && pc.z() > 0 && v.current.in_bounds(uv.x(), uv.y()) &&
                        dist >= mp->min_distance_invariance() && dist <= mp->max_distance_invariance();
    if (!mp->track.in_view) continue;
    ++in_view;
    mp->track.proj_x = static_cast<float>(uv.x());
    mp->track.proj_y = static_cast<float>(uv.y());
    mp->track.proj_xr = static_cast<float>(uv.x() - cam.bf / pc.z());
    mp->track.view_cos = static_cast<float>(po.dot(mp->normal()) / dist);
    mp->track.scale_level = mp->predict_scale(dist, std::log(sf[1]), static_cast<int>(sf.size()));
  }
  return in_view;
}

constexpr float kMotionRadius = 15.0f;  // the tracker's motion-model radius for RGB-D

// The orientation bin of a match (angles a, b) by the public interface: the bin whose dominant
// set of matches does not make the histogram reject it.
int bin_of(float a, float b) {
  for (int bin = 0; bin < lrd::match::RotationHistogram::kBins; ++bin) {
    lrd::match::RotationHistogram probe;
    probe.add(a, b, 0);
    for (int k = 0; k < 20; ++k) probe.add(static_cast<float>(bin) * 12.0f, 0.0f, 1);
    if (probe.rejected().empty()) return bin;
  }
  return -1;
}

}  // namespace

TEST(OrbMatcher, SearchByProjectionFromLastFrameSidewaysForwardBackward) {
  struct Motion {
    const char* name;
    Eigen::Isometry3d T1;
    int min_level_change, max_level_change;  // allowed octave(current) - octave(last)
  };
  // Sideways with a small rotation: levels within one of the last one. 25 cm forward: points
  // come closer and look larger, so only the same or coarser levels; 25 cm backward: the same or
  // finer levels.
  const Motion motions[] = {{"sideways", lrd::test::pose(0.02, -0.04, 0.03, 0.12, -0.03, 0.02), -1, 1},
                            {"forward", lrd::test::pose(0.01, 0.02, 0.0, 0.02, 0.0, -0.25), 0, 7},
                            {"backward", lrd::test::pose(-0.01, 0.0, 0.02, 0.0, 0.03, 0.25), -7, 0}};
  for (const Motion& m : motions) {
    SCOPED_TRACE(m.name);
    TwoViews v(kIdentity, m.T1);
    const int n = OrbMatcher().search_by_projection(v.current, v.last, kMotionRadius);
    const Tally t = check_frame_matches(v.scene, v.current, v.T1);
    EXPECT_EQ(n, t.matches);
    EXPECT_GT(t.matches, 300);
    // No ratio test here (guided search up to TH_HIGH): keypoints not re-detected take a
    // neighbour. Pose optimization removes those; most must be right.
    EXPECT_GE(t.ratio(), 0.85) << t.correct << " of " << t.matches;
    int changed = 0;
    for (std::size_t j = 0; j < v.current.size(); ++j) {
      const MapPoint* mp = v.current.map_points[j];
      if (mp == nullptr) continue;
      const int change = v.current.undistorted()[j].octave - v.last.undistorted()[*mp->index_in(v.kf)].octave;
      EXPECT_GE(change, m.min_level_change);
      EXPECT_LE(change, m.max_level_change);
      changed += change != 0;
    }
    EXPECT_GT(changed, 0);
  }
}

TEST(OrbMatcher, SearchByProjectionFromLastFrameRotationCheckRaisesPrecision) {
  TwoViews v(kIdentity, lrd::test::pose(0.02, -0.04, 0.03, 0.12, -0.03, 0.02));
  Frame unchecked = v.current;
  OrbMatcher().search_by_projection(v.current, v.last, kMotionRadius);
  OrbMatcher(MatcherParams{0.6f, false}).search_by_projection(unchecked, v.last, kMotionRadius);
  const Tally with = check_frame_matches(v.scene, v.current, v.T1);
  const Tally without = check_frame_matches(v.scene, unchecked, v.T1);
  EXPECT_GT(without.matches, with.matches);
  EXPECT_LT(with.wrong(), without.wrong() / 2);
  EXPECT_GT(with.ratio(), without.ratio() + 0.05);
}

TEST(OrbMatcher, SearchByProjectionFromLastFrameSkipsOutliersAndTakenKeypoints) {
  TwoViews v(kIdentity, lrd::test::pose(0.0, 0.03, 0.0, 0.08, 0.02, 0.0));
  // Every other match of the last frame is flagged an outlier: those points must not be matched.
  std::set<const MapPoint*> flagged;
  for (std::size_t i = 0; i < v.last.size(); i += 2) {
    if (v.last.map_points[i] == nullptr) continue;
    v.last.outliers[i] = true;
    flagged.insert(v.last.map_points[i]);
  }
  // Keypoints of the current frame that already hold an observed map point stay as they are.
  MapPoint* holder = *std::find_if(v.kf->map_points().begin(), v.kf->map_points().end(),
                                   [](MapPoint* p) { return p != nullptr; });
  for (std::size_t j = 0; j < v.current.size(); j += 5) v.current.map_points[j] = holder;
  const int n = OrbMatcher().search_by_projection(v.current, v.last, kMotionRadius);
  EXPECT_GT(n, 150);
  int matched = 0, correct = 0;
  for (std::size_t j = 0; j < v.current.size(); ++j) {
    MapPoint* mp = v.current.map_points[j];
    if (j % 5 == 0) {
      EXPECT_EQ(mp, holder);
      continue;
    }
    if (mp == nullptr) continue;
    ++matched;
    EXPECT_EQ(flagged.count(mp), 0u);
    correct += right(v.scene, v.current, j, v.T1, mp->position());
  }
  EXPECT_EQ(matched, n);
  EXPECT_GE(correct, 0.85 * n);
}

TEST(OrbMatcher, SearchByProjectionOfLocalMapPointsInView) {
  TwoViews v(kIdentity, lrd::test::pose(-0.03, 0.02, -0.02, -0.1, 0.05, 0.08));
  // Every third point is declared out of view and must stay unmatched.
  std::vector<MapPoint*> points;
  std::set<const MapPoint*> hidden;
  const int in_view = project_local_points(v, points, &hidden);
  ASSERT_GT(in_view, 300);
  const int n = OrbMatcher().search_by_projection(v.current, points, 1.0f);
  const Tally t = check_frame_matches(v.scene, v.current, v.T1);
  EXPECT_EQ(n, t.matches);
  EXPECT_GT(t.matches, 200);
  EXPECT_GE(t.ratio(), 0.95) << t.correct << " of " << t.matches;
  for (const MapPoint* mp : v.current.map_points) EXPECT_EQ(hidden.count(mp), 0u);
}

TEST(OrbMatcher, SearchByProjectionOfLocalMapPointsChecksTheVirtualRightCoordinate) {
  // A keypoint with depth is a candidate only if its virtual right coordinate agrees with the
  // projected one within the search radius (th * 2.5 * scale of the predicted level, the same
  // radius as the search window, as ORB-SLAM2). One map point per keypoint of level >= 1 with
  // depth, carrying that keypoint's own descriptor and projected exactly onto it; only the
  // projected right coordinate is off, by 0.9 or 1.1 radii.
  TexturedPlane scene;
  Map map;
  const Frame frame = scene.frame(0, kIdentity);
  constexpr float th = 1.0f;
  auto run = [&](float fraction) {
    Frame current = frame;
    std::vector<MapPoint*> points;
    std::vector<std::size_t> target;
    for (std::size_t j = 0; j < current.size(); ++j) {
      const cv::KeyPoint& kp = current.undistorted()[j];
      if (kp.octave < 1 || current.u_right(j) <= 0.0f) continue;
      MapPoint* mp = map.create_map_point(Eigen::Vector3d(0, 0, 2), nullptr, 0);
      mp->set_descriptor(current.descriptors().row(static_cast<int>(j)).clone());
      const float radius = 2.5f * th * current.scale_factors()[static_cast<std::size_t>(kp.octave)];
      mp->track.in_view = true;
      mp->track.proj_x = kp.pt.x;
      mp->track.proj_y = kp.pt.y;
      mp->track.proj_xr = current.u_right(j) + fraction * radius;
      mp->track.scale_level = kp.octave;
      mp->track.view_cos = 1.0f;
      points.push_back(mp);
      target.push_back(j);
    }
    OrbMatcher().search_by_projection(current, points, th);
    int own = 0;
    for (std::size_t k = 0; k < points.size(); ++k) own += current.map_points[target[k]] == points[k];
    return std::make_pair(own, static_cast<int>(points.size()));
  };
  const auto [inside, n] = run(0.9f);
  ASSERT_GT(n, 300);
  EXPECT_GE(inside, 0.95 * n);
  const auto [outside, n2] = run(1.1f);
  EXPECT_EQ(outside, 0) << "of " << n2;
}

TEST(OrbMatcher, SearchByDescriptorAgainstAKeyFrame) {
  // No pose is used: the current view is rolled by about 23 degrees and moved.
  TwoViews v(kIdentity, lrd::test::pose(0.0, 0.0, 0.40, 0.05, 0.0, -0.05));
  const int n = OrbMatcher().search_by_descriptor(*v.kf, v.current);
  const Tally t = check_frame_matches(v.scene, v.current, v.T1);
  EXPECT_EQ(n, t.matches);
  EXPECT_GT(t.matches, 150);
  EXPECT_GE(t.ratio(), 0.97) << t.correct << " of " << t.matches;
  // Every match is a map point of the keyframe, within kThLow.
  const std::set<MapPoint*> kf_points(v.kf->map_points().begin(), v.kf->map_points().end());
  for (std::size_t j = 0; j < v.current.size(); ++j) {
    MapPoint* mp = v.current.map_points[j];
    if (mp == nullptr) continue;
    EXPECT_EQ(kf_points.count(mp), 1u);
    const std::size_t i = *mp->index_in(v.kf);
    EXPECT_LE(cv::norm(v.kf->features().descriptors().row(static_cast<int>(i)),
                       v.current.descriptors().row(static_cast<int>(j)), cv::NORM_HAMMING),
              OrbMatcher::kThLow);
  }
}

TEST(OrbMatcher, SearchByDescriptorRotationCheckDropsInconsistentMatches) {
  // Ratio test off (1.0): some wrong matches get through. The rotation check removes most of
  // them, keeps most right ones, and what it keeps lies in at most three orientation bins.
  TwoViews v(kIdentity, lrd::test::pose(0.0, 0.0, 0.40, 0.05, 0.0, -0.05));
  Frame loose = v.current, checked = v.current;
  const int n_loose = OrbMatcher(MatcherParams{1.0f, false}).search_by_descriptor(*v.kf, loose);
  const int n_checked = OrbMatcher(MatcherParams{1.0f, true}).search_by_descriptor(*v.kf, checked);
  const Tally tl = check_frame_matches(v.scene, loose, v.T1),
              tc = check_frame_matches(v.scene, checked, v.T1);
  EXPECT_EQ(n_loose, tl.matches);
  EXPECT_EQ(n_checked, tc.matches);
  ASSERT_GE(tl.wrong(), 3);
  EXPECT_LE(tc.wrong(), tl.wrong() / 3);
  EXPECT_GE(tc.correct, 0.9 * tl.correct);
  std::set<int> bins;
  for (std::size_t j = 0; j < checked.size(); ++j) {
    if (checked.map_points[j] == nullptr) continue;
    EXPECT_EQ(checked.map_points[j], loose.map_points[j]);  // a subset of the unchecked matches
    const std::size_t i = *checked.map_points[j]->index_in(v.kf);
    bins.insert(bin_of(v.kf->features().undistorted()[i].angle, checked.undistorted()[j].angle));
  }
  EXPECT_LE(bins.size(), 3u);
  EXPECT_EQ(bins.count(-1), 0u);
}

TEST(OrbMatcher, SearchForTriangulationFollowsTheEpipolarGeometry) {
  TexturedPlane scene;
  Map map;
  const Eigen::Isometry3d T1 = kIdentity;
  const Eigen::Isometry3d T2 = lrd::test::pose(0.01, -0.05, 0.01, 0.25, 0.02, 0.03);
  KeyFrame* kf1 = map.create_keyframe(scene.frame(0, T1));
  KeyFrame* kf2 = map.create_keyframe(scene.frame(1, T2));
  // Keypoints that already have a map point are no candidates.
  MapPoint* dummy = map.create_map_point(Eigen::Vector3d(0, 0, 2), kf1, 0);
  for (std::size_t i = 0; i < kf1->size(); i += 4) kf1->add_map_point(dummy, i);
  for (std::size_t j = 1; j < kf2->size(); j += 7) kf2->add_map_point(dummy, j);

  const Eigen::Matrix3d F12 = lrd::geometry::fundamental_matrix(T1, T2, scene.camera().K());
  const auto pairs = OrbMatcher().search_for_triangulation(*kf1, *kf2, F12);
  const Frame& f1 = kf1->features();
  const Frame& f2 = kf2->features();
  std::set<std::size_t> used1, used2;
  int correct = 0;
  for (const auto& [i, j] : pairs) {
    EXPECT_NE(i % 4, 0u);
    EXPECT_NE(j % 7, 1u);
    EXPECT_TRUE(used1.insert(i).second);
    EXPECT_TRUE(used2.insert(j).second);
    EXPECT_LE(cv::norm(f1.descriptors().row(static_cast<int>(i)), f2.descriptors().row(static_cast<int>(j)),
                       cv::NORM_HAMMING),
              OrbMatcher::kThLow);
    // Within the chi-square band (3.84 sigma^2) around the epipolar line x1' F12.
    const cv::Point2f& a = f1.undistorted()[i].pt;
    const cv::Point2f& b = f2.undistorted()[j].pt;
    const Eigen::Vector3d l = F12.transpose() * Eigen::Vector3d(a.x, a.y, 1.0);
    const double dist2 = std::pow(l.dot(Eigen::Vector3d(b.x, b.y, 1.0)), 2) / l.head<2>().squaredNorm();
    EXPECT_LT(dist2, 3.84 * f2.level_sigma2()[static_cast<std::size_t>(f2.undistorted()[j].octave)]);
    // Geometrically right: where kf1's keypoint ray meets the plane, kf2's keypoint sees it.
    correct += right(scene, f2, j, T2, scene.true_point(f1, i, T1));
  }
  EXPECT_GT(pairs.size(), 150u);
  EXPECT_GE(correct, 0.95 * static_cast<double>(pairs.size())) << correct << " of " << pairs.size();
  // With the F of a wrong pose (moved down instead of sideways) the search finds few right pairs.
  const Eigen::Matrix3d F_wrong = lrd::geometry::fundamental_matrix(
      T1, lrd::test::pose(0.01, -0.05, 0.01, 0.02, 0.25, 0.03), scene.camera().K());
  const auto bad = OrbMatcher().search_for_triangulation(*kf1, *kf2, F_wrong);
  int bad_correct = 0;
  for (const auto& [i, j] : bad) bad_correct += right(scene, f2, j, T2, scene.true_point(f1, i, T1));
  EXPECT_LT(bad.size(), pairs.size() / 4);
  EXPECT_LT(bad_correct, correct / 10);
}

TEST(OrbMatcher, FuseMergesDuplicatePoints) {
  // The target keyframe has its own points for the same corners: each fusion merges two points.
  TexturedPlane scene;
  Map map;
  const Eigen::Isometry3d T1 = lrd::test::pose(0.02, 0.03, -0.01, 0.1, -0.04, 0.03);
  KeyFrame* kf0 = lrd::test::keyframe_with_points(map, scene.frame(0, kIdentity));
  KeyFrame* kf1 = lrd::test::keyframe_with_points(map, scene.frame(1, T1));
  const std::vector<MapPoint*> points0 = kf0->map_points();
  const std::vector<MapPoint*> originals1 = kf1->map_points();
  const std::size_t before = map.map_point_count();
  const int fused = OrbMatcher().fuse(*kf1, points0);
  EXPECT_GT(fused, 250);
  // Every fusion removes exactly one point.
  EXPECT_EQ(map.map_point_count(), before - static_cast<std::size_t>(fused));
  int merged = 0, correct = 0;
  for (std::size_t j = 0; j < kf1->size(); ++j) {
    MapPoint* now = kf1->map_point(j);
    MapPoint* was = originals1[j];
    if (was == nullptr || now == was) continue;
    ++merged;
    // Equal observation counts: the keyframe's own point gives way to the projected one.
    ASSERT_NE(now, nullptr);
    EXPECT_TRUE(was->is_bad());
    EXPECT_EQ(was->replaced_by(), now);
    EXPECT_TRUE(now->is_in_keyframe(kf0));
    EXPECT_EQ(now->index_in(kf1), j);
    EXPECT_EQ(now->num_observations(), 4);
    correct += right(scene, kf1->features(), j, T1, now->position());
  }
  EXPECT_GE(correct, 0.95 * merged);
  // The other fusions merged two of kf0's own points that met at one keypoint of kf1 (the same
  // corner detected on two pyramid levels): the loser now points at a survivor in both views.
  int duplicates = 0;
  for (MapPoint* mp : points0) {
    if (mp == nullptr || !mp->is_bad()) continue;
    ++duplicates;
    MapPoint* survivor = mp->replaced_by();
    ASSERT_NE(survivor, nullptr);
    EXPECT_TRUE(survivor->is_in_keyframe(kf0));
    EXPECT_TRUE(survivor->is_in_keyframe(kf1));
    EXPECT_LT((survivor->position() - mp->position()).norm(), 0.05);
  }
  EXPECT_EQ(merged + duplicates, fused);
  EXPECT_LT(duplicates, merged / 5);
}

TEST(OrbMatcher, FuseAddsObservationsToAKeyFrameWithoutPoints) {
  TexturedPlane scene;
  Map map;
  const Eigen::Isometry3d T1 = lrd::test::pose(0.02, 0.03, -0.01, 0.1, -0.04, 0.03);
  KeyFrame* kf0 = lrd::test::keyframe_with_points(map, scene.frame(0, kIdentity));
  KeyFrame* kf1 = map.create_keyframe(scene.frame(1, T1));
  const int fused = OrbMatcher().fuse(*kf1, kf0->map_points());
  EXPECT_GT(fused, 250);
  int added = 0, correct = 0;
  for (std::size_t j = 0; j < kf1->size(); ++j) {
    MapPoint* mp = kf1->map_point(j);
    if (mp == nullptr) continue;
    ++added;
    EXPECT_FALSE(mp->is_bad());
    EXPECT_EQ(mp->index_in(kf1), j);
    EXPECT_TRUE(mp->is_in_keyframe(kf0));
    correct += right(scene, kf1->features(), j, T1, mp->position());
  }
  EXPECT_GE(correct, 0.95 * added);
  EXPECT_LE(added, fused);
  EXPECT_GT(added, 0.8 * fused);
  // Points already in the keyframe are skipped: fusing again changes nothing.
  EXPECT_EQ(OrbMatcher().fuse(*kf1, kf0->map_points()), 0);
}
