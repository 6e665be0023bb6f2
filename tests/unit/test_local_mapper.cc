// Local mapping in lock-step mode (threaded = false, process_queued()) on keyframes of a rendered
// textured plane made the way tracking makes them: new points are triangulated from keypoints
// without depth where the plane really is, not at all over a baseline shorter than the depth
// sensor's own, recent points that tracking fails to find are culled within their watch window
// (and only then), redundant keyframes are removed, and each keyframe is indexed for place
// recognition and handed on in order.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <vector>

#include "lrd/geometry/triangulation.h"
#include "lrd/mapping/local_mapper.h"
#include "map_scene.h"

using lrd::data::Frame;
using lrd::map::KeyFrame;
using lrd::map::MapPoint;
using lrd::mapping::LocalMapper;
using lrd::mapping::LocalMapperParams;

namespace {

// Local BA and keyframe culling off unless a test is about them: each step on its own.
LocalMapperParams plain_params() {
  LocalMapperParams p;
  p.local_ba = false;
  p.keyframe_culling = false;
  return p;
}

// For the culling tests: keyframes that are exact copies of each other leave duplicate fusion with
// borderline decisions (a neighbouring keypoint at the search radius) that differ between
// optimization levels; culling is judged without it.
LocalMapperParams culling_params() {
  LocalMapperParams p = plain_params();
  p.fuse_neighbours = 0;
  p.fuse_second_neighbours = 0;
  return p;
}

// Two views of the plane, the second `baseline` metres to the right. The right half of both
// images has no depth, as far or unmeasured surfaces have none: tracking gives those keypoints
// no map point, only triangulation can. Keyframe 0 has a point for every keypoint with depth
// (map initialization); keyframe 1 matches them by projection and makes its own from depth.
struct TwoViews {
  lrd::test::TexturedPlane plane;
  lrd::map::Map map;
  Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity(), T1;
  KeyFrame *kf0 = nullptr, *kf1 = nullptr;
  int matches = 0;
  std::size_t points_before_mapping = 0;

  explicit TwoViews(double baseline) : T1(lrd::test::pose(0.0, 0.0, 0.0, -baseline, 0.0, 0.0)) {
    cv::Mat no_depth = cv::Mat::zeros(480, 640, CV_8U);
    no_depth.colRange(320, 640).setTo(255);
    kf0 = lrd::test::keyframe_with_points(map, plane.frame(0, T0, no_depth));
    Frame f1 = plane.frame(1, T1, no_depth);
    matches = lrd::test::associate(f1, lrd::test::points_of(kf0));
    kf1 = lrd::test::tracking_keyframe(map, f1);
    points_before_mapping = map.map_point_count();
  }
  // Keypoints with neither depth nor map point.
  static int free_mono(const KeyFrame* kf) {
    int n = 0;
    for (std::size_t i = 0; i < kf->size(); ++i)
      n += kf->map_point(i) == nullptr && kf->features().u_right(i) < 0.0f;
    return n;
  }
  // Points local mapping created (ids after those tracking made).
  [[nodiscard]] std::vector<MapPoint*> created_by_mapping() const {
    std::vector<MapPoint*> out;
    for (MapPoint* mp : map.map_points())
      if (mp->id() >= points_before_mapping) out.push_back(mp);
    return out;
  }
};

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

}  // namespace

TEST(LocalMapper, TriangulatesKeypointsWithoutDepthOntoThePlane) {
  TwoViews s(0.25);
  const double sensor_baseline = s.plane.camera().baseline();
  ASSERT_GT((s.kf1->camera_center() - s.kf0->camera_center()).norm(), sensor_baseline);
  ASSERT_GT(s.matches, 150);
  ASSERT_GT(TwoViews::free_mono(s.kf0), 150);
  ASSERT_GT(TwoViews::free_mono(s.kf1), 150);

  LocalMapper mapper(s.map, plain_params(), false);
  mapper.insert_keyframe(s.kf0);
  mapper.process_queued();
  EXPECT_EQ(mapper.stats().triangulated_points, 0u);  // nothing to pair with yet
  mapper.insert_keyframe(s.kf1);
  mapper.process_queued();
  const auto stats = mapper.stats();
  EXPECT_EQ(stats.keyframes, 2u);
  EXPECT_EQ(stats.bundle_adjustments, 0u);

  // Tracking's matches became observations and covisibility.
  EXPECT_EQ(s.kf1->parent(), s.kf0);
  EXPECT_GE(s.kf1->weight(s.kf0), s.matches);

  const std::vector<MapPoint*> created = s.created_by_mapping();
  ASSERT_GT(created.size(), 100u);
  EXPECT_LE(created.size(), stats.triangulated_points);  // a few may be fused away afterwards
  EXPECT_GE(created.size() + 10, stats.triangulated_points);
  std::vector<double> errors, across;  // metres
  for (MapPoint* mp : created) {
    // Seen by both keyframes through keypoints without depth.
    const auto i0 = mp->index_in(s.kf0), i1 = mp->index_in(s.kf1);
    ASSERT_TRUE(i0 && i1) << mp->id();
    EXPECT_LT(s.kf0->features().u_right(*i0), 0.0f);
    EXPECT_LT(s.kf1->features().u_right(*i1), 0.0f);
    EXPECT_EQ(s.kf0->map_point(*i0), mp);
    EXPECT_EQ(s.kf1->map_point(*i1), mp);
    // Where the plane is behind the keypoint.
    const Eigen::Vector3d truth = s.plane.true_point(s.kf0->features(), *i0, s.T0);
    const Eigen::Vector3d d = mp->position() - truth;
    const Eigen::Vector3d ray = truth.normalized();  // camera 0 sits at the origin
    errors.push_back(d.norm());
    across.push_back((d - d.dot(ray) * ray).norm());
  }
  // Across the ray the keypoint's pixel bounds the error (a pixel is 4 mm at 2 m); along it, a
  // pixel of disparity over 25 cm is 3.6 cm, and higher pyramid levels have coarser keypoints.
  // Measured: across the ray at most 8 mm (median 0); the error median 2.1 cm, 90 % under
  // 5.7 cm, none over 11 cm.
  EXPECT_LT(quantile(across, 0.5), 0.002);
  EXPECT_LT(quantile(across, 1.0), 0.015);
  EXPECT_LT(quantile(errors, 0.5), 0.03);
  EXPECT_LT(quantile(errors, 0.9), 0.08);
  EXPECT_LT(quantile(errors, 1.0), 0.15);
}

TEST(LocalMapper, BaselineShorterThanTheSensorsTriangulatesNothing) {
  TwoViews s(0.05);
  ASSERT_LT((s.kf1->camera_center() - s.kf0->camera_center()).norm(), s.plane.camera().baseline());
  // Precondition: there would be candidates to triangulate.
  const lrd::match::OrbMatcher matcher(lrd::match::MatcherParams{0.6f, false});
  const Eigen::Matrix3d F = lrd::geometry::fundamental_matrix(s.T1, s.T0, s.plane.camera().K());
  ASSERT_GT(matcher.search_for_triangulation(*s.kf1, *s.kf0, F).size(), 100u);

  LocalMapper mapper(s.map, plain_params(), false);
  mapper.insert_keyframe(s.kf0);
  mapper.insert_keyframe(s.kf1);
  mapper.process_queued();
  EXPECT_EQ(mapper.stats().keyframes, 2u);
  EXPECT_EQ(mapper.stats().triangulated_points, 0u);
  EXPECT_TRUE(s.created_by_mapping().empty());
  EXPECT_EQ(s.kf1->parent(), s.kf0);
}

namespace {

// Copies of one rendered view at one pose (no baseline: nothing is triangulated), keyframe 0 with
// a point for every keypoint with depth.
struct Copies {
  lrd::map::Map map;
  KeyFrame* kf0 = nullptr;
  std::vector<MapPoint*> points;                 // keyframe 0's, by keypoint order
  std::map<const MapPoint*, std::size_t> index;  // their keypoints (kept when they go bad)

  static const Frame& view() {
    static const Frame frame = [] {
      lrd::test::TexturedPlane plane;
      return plane.frame(0, Eigen::Isometry3d::Identity());
    }();
    return frame;
  }
  // Points only for keypoints of the finest level with no other keypoint within 4 pixels: on a
  // copy of the same view duplicate fusion then has nothing to merge, and each point's fate is
  // decided by the culling rules alone.
  Copies() {
    const Frame& f = view();
    kf0 = map.create_keyframe(f);
    for (std::size_t i = 0; i < f.size(); ++i) {
      const cv::KeyPoint& kp = f.undistorted()[i];
      // With a virtual right coordinate (depth near the left border has none): weight 2 each.
      if (kp.octave != 0 || f.depth(i) <= 0.0f || f.u_right(i) < 0.0f) continue;
      if (f.features_in_area(kp.pt.x, kp.pt.y, 4.0f).size() > 1) continue;
      MapPoint* mp = map.create_map_point(*f.unproject_world(i), kf0, f.id());
      mp->add_observation(kf0, i);
      kf0->add_map_point(mp, i);
      mp->compute_distinctive_descriptor();
      mp->update_normal_and_depth();
    }
    points = lrd::test::points_of(kf0);
    for (const MapPoint* mp : points) index[mp] = *mp->index_in(kf0);
  }
  // A keyframe of the same view in which tracking matched `matched` (by keypoint) and whose
  // keypoints under `gone` were not detected at all.
  KeyFrame* keyframe(const std::vector<MapPoint*>& matched, const std::vector<MapPoint*>& gone = {}) {
    Frame f = view();
    std::vector<bool> drop(f.size(), false);
    for (const MapPoint* mp : gone) drop[index.at(mp)] = true;
    std::vector<std::size_t> new_index(f.size(), SIZE_MAX);
    for (std::size_t i = 0, kept = 0; i < f.size(); ++i)
      if (!drop[i]) new_index[i] = kept++;
    f.remove_keypoints(drop);
    for (MapPoint* mp : matched) f.map_points[new_index[index.at(mp)]] = mp;
    return map.create_keyframe(f);
  }
};

std::vector<MapPoint*> every_fifth(const std::vector<MapPoint*>& v, std::size_t offset) {
  std::vector<MapPoint*> out;
  for (std::size_t i = offset; i < v.size(); i += 5) out.push_back(v[i]);
  return out;
}
std::vector<MapPoint*> join(std::vector<MapPoint*> a, const std::vector<MapPoint*>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}
int bad_count(const std::vector<MapPoint*>& v) {
  return static_cast<int>(std::count_if(v.begin(), v.end(), [](const MapPoint* mp) { return mp->is_bad(); }));
}

}  // namespace

TEST(LocalMapper, CullsRecentPointsTrackingLosesWithinTheirWatchWindow) {
  Copies c;
  ASSERT_GE(c.points.size(), 50u);
  // Keyframe 0's points in five kinds (ORB-SLAM2's MapPointCulling, RGB-D: 3 observations):
  const auto rarely_found =
      every_fifth(c.points, 0);  // found in under 25 % of the frames that should see them
  const auto never_again = every_fifth(c.points, 1);  // never matched by a later keyframe (not even detected)
  const auto lost_early = every_fifth(c.points, 2);   // matched twice, then rarely found while watched
  const auto kept = every_fifth(c.points, 3);         // matched by every keyframe
  const auto lost_late = every_fifth(c.points, 4);    // matched, rarely found once no longer watched
  for (MapPoint* mp : rarely_found) mp->increase_visible(9);  // found 1 of 10

  LocalMapper mapper(c.map, culling_params(), false);
  mapper.insert_keyframe(c.kf0);
  mapper.process_queued();
  EXPECT_EQ(bad_count(rarely_found), static_cast<int>(rarely_found.size()));  // at once
  EXPECT_EQ(bad_count(never_again) + bad_count(lost_early) + bad_count(kept) + bad_count(lost_late), 0);

  const auto all_matched = join(join(lost_early, kept), lost_late);
  KeyFrame* kf1 = c.keyframe(all_matched, never_again);
  mapper.insert_keyframe(kf1);
  mapper.process_queued();
  EXPECT_EQ(bad_count(never_again), 0);  // one keyframe later: still given a chance
  for (MapPoint* mp : kept) EXPECT_EQ(mp->num_observations(), 4);
  for (MapPoint* mp : lost_early) mp->increase_visible(9);

  KeyFrame* kf2 = c.keyframe(all_matched, never_again);
  mapper.insert_keyframe(kf2);
  mapper.process_queued();
  EXPECT_EQ(bad_count(never_again), static_cast<int>(never_again.size()));  // 2 keyframes on, 1 view
  EXPECT_EQ(bad_count(lost_early), static_cast<int>(lost_early.size()));    // found 1 of 10
  EXPECT_EQ(bad_count(kept) + bad_count(lost_late), 0);

  KeyFrame* kf3 = c.keyframe(join(kept, lost_late), never_again);
  mapper.insert_keyframe(kf3);
  mapper.process_queued();  // 3 keyframes on: no longer watched
  for (MapPoint* mp : lost_late) mp->increase_visible(30);
  KeyFrame* kf4 = c.keyframe(kept, never_again);
  mapper.insert_keyframe(kf4);
  mapper.process_queued();
  EXPECT_EQ(bad_count(kept) + bad_count(lost_late), 0);
  EXPECT_EQ(c.map.map_point_count(), kept.size() + lost_late.size());
  for (MapPoint* mp : kept) EXPECT_EQ(mp->num_observations(), 10);
  for (MapPoint* mp : lost_late) EXPECT_GE(mp->num_observations(), 8);  // 10 if fusion finds them in kf4
  EXPECT_EQ(mapper.stats().triangulated_points, 0u);
  EXPECT_EQ(c.map.keyframe_count(), 5u);
}

TEST(LocalMapper, RemovesKeyFramesWhosePointsThreeOthersSee) {
  Copies c;
  ASSERT_GE(c.points.size(), 50u);
  LocalMapperParams params = culling_params();
  params.keyframe_culling = true;
  LocalMapper mapper(c.map, params, false);
  mapper.insert_keyframe(c.kf0);
  mapper.process_queued();
  // Keyframes by id: a culled one is freed once the mapper moves on (map/reclamation.h).
  std::vector<std::uint64_t> kfs = {c.kf0->id()};
  std::vector<std::vector<std::uint64_t>> alive_after;
  for (int k = 1; k <= 4; ++k) {
    KeyFrame* kf = c.keyframe(c.points);
    kfs.push_back(kf->id());
    mapper.insert_keyframe(kf);
    mapper.process_queued();
    alive_after.emplace_back();
    for (const KeyFrame* alive : c.map.keyframes()) alive_after.back().push_back(alive->id());
  }
  // Every point is seen by every keyframe at the same scale. When keyframe 3 arrives, keyframe 1's
  // points have three other observers (0, 2, 3): it goes, and keyframe 2 is left with two. When
  // keyframe 4 arrives, keyframe 2's points have three again (0, 3, 4). Keyframe 0 never goes.
  using Ids = std::vector<std::uint64_t>;
  EXPECT_EQ(alive_after[0], (Ids{kfs[0], kfs[1]}));
  EXPECT_EQ(alive_after[1], (Ids{kfs[0], kfs[1], kfs[2]}));
  EXPECT_EQ(alive_after[2], (Ids{kfs[0], kfs[2], kfs[3]}));
  EXPECT_EQ(alive_after[3], (Ids{kfs[0], kfs[3], kfs[4]}));
  EXPECT_EQ(mapper.stats().culled_keyframes, 2u);
  EXPECT_EQ(c.map.map_point_count(), c.points.size());
  for (MapPoint* mp : c.points) {
    EXPECT_EQ(mp->num_observations(), 6);
    for (const auto& [kf, index] : mp->observations()) EXPECT_NE(kf->id(), kfs[1]);
  }
  EXPECT_EQ(c.map.keyframe(kfs[4])->parent(), c.kf0);
  EXPECT_EQ(c.map.keyframe(kfs[3])->parent(), c.kf0);
  // Keyframe 1 was freed when the mapper moved on to keyframe 4; keyframe 2, culled while
  // keyframe 4 was mapped, waits for the mapper's next keyframe.
  EXPECT_EQ(c.map.memory().reclamation.freed_keyframes, 1u);
  EXPECT_EQ(c.map.memory().reclamation.waiting_keyframes, 1u);
}

TEST(LocalMapper, IndexesKeyFramesForPlaceRecognitionAndHandsThemOnInOrder) {
  Copies c;
  lrd::map::KeyFrameDatabase db;
  const auto& vocabulary = lrd::test::shipped_vocabulary();
  LocalMapper mapper(c.map, plain_params(), false);
  mapper.set_place_recognition(&vocabulary, &db);
  std::vector<KeyFrame*> handed;
  mapper.set_keyframe_callback([&](KeyFrame* kf) {
    EXPECT_EQ(db.size(), handed.size() + 1) << "indexed before it is handed on";
    handed.push_back(kf);
  });
  KeyFrame* kf1 = c.keyframe(c.points);
  KeyFrame* kf2 = c.keyframe(c.points);
  mapper.insert_keyframe(c.kf0);
  mapper.insert_keyframe(kf1);
  EXPECT_EQ(mapper.queued(), 2u);
  mapper.process_queued();
  mapper.insert_keyframe(kf2);
  mapper.process_queued();
  EXPECT_EQ(mapper.queued(), 0u);
  EXPECT_EQ(handed, (std::vector<KeyFrame*>{c.kf0, kf1, kf2}));
  EXPECT_EQ(db.size(), 3u);
  lrd::place::BowVector expected;
  vocabulary.transform(Copies::view().descriptors(), expected);
  ASSERT_FALSE(expected.empty());
  for (KeyFrame* kf : handed) EXPECT_EQ(kf->bow(), expected);
  // Indexed: the database finds them for a lost frame with the same view.
  Frame lost = Copies::view();
  lost.compute_bow(vocabulary);
  const auto found = db.relocalization_candidates(lost);
  ASSERT_FALSE(found.empty());
  EXPECT_EQ(found, (std::vector<KeyFrame*>{c.kf0, kf1, kf2}));  // identical views: all alike, oldest first
}

// The callback gets only keyframes "once processed and still in the map": one removed while it
// was queued is neither processed, counted nor handed on.
TEST(LocalMapper, DoesNotHandOnAKeyFrameRemovedWhileQueued) {
  Copies c;
  LocalMapper mapper(c.map, plain_params(), false);
  std::vector<KeyFrame*> handed;
  mapper.set_keyframe_callback([&](KeyFrame* kf) { handed.push_back(kf); });
  KeyFrame* kf1 = c.keyframe({});
  mapper.insert_keyframe(c.kf0);
  mapper.insert_keyframe(kf1);
  kf1->set_bad();
  ASSERT_TRUE(kf1->is_bad());
  mapper.process_queued();
  EXPECT_EQ(handed, std::vector<KeyFrame*>{c.kf0});
  EXPECT_EQ(mapper.stats().keyframes, 1u);
}
