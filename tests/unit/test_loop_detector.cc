// Loop detection with the shipped vocabulary on a camera that comes back (map_scene.h's
// LoopScene: four keyframes of a textured plane, then the same four views again with a drifted
// pose and a map of their own): a candidate closes the loop only once it has been consistent
// over four consecutive keyframes (the default consistency 3), a keyframe without candidates
// breaks the chain, after a closed loop the next one waits, and a look-alike whose 3-D structure
// disagrees is no loop. A detected loop names the right keyframe and measures the pose the
// current keyframe really has in the old map.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "lrd/loop/loop_detector.h"
#include "map_scene.h"

using lrd::loop::LoopDetection;
using lrd::loop::LoopDetector;
using lrd::loop::LoopDetectorParams;
using lrd::map::KeyFrame;
using lrd::map::MapPoint;
using lrd::test::LoopScene;

namespace {

bool contains(const std::vector<KeyFrame*>& v, const KeyFrame* kf) {
  return std::find(v.begin(), v.end(), kf) != v.end();
}

// Each keyframe of the second visit finds the view it repeats among its loop candidates.
void assert_candidates(LoopScene& s, lrd::map::KeyFrameDatabase& db) {
  for (std::size_t k = 0; k < s.back.size(); ++k)
    ASSERT_TRUE(contains(db.loop_candidates(s.back[k], 0.0), s.first[k])) << "second visit " << k;
}

}  // namespace

TEST(LoopDetector, ClosesTheLoopOnceTheCandidateIsConsistentOverFourKeyFrames) {
  lrd::map::KeyFrameDatabase db;
  LoopScene s(&db);
  s.add_first_visit();
  s.add_second_visit();
  ASSERT_EQ(s.back.size(), 4u);
  assert_candidates(s, db);
  for (KeyFrame* kf : s.back) ASSERT_FALSE(kf->ordered_covisibles().empty());

  LoopDetector detector(db, LoopDetectorParams{});
  for (int k = 0; k < 3; ++k) EXPECT_FALSE(detector.detect(s.back[static_cast<std::size_t>(k)])) << k;
  const auto d = detector.detect(s.back[3]);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->current, s.back[3]);
  EXPECT_EQ(d->loop, s.first[3]);  // the very view it repeats
  // In the old map the current keyframe sits where the view really was taken.
  EXPECT_LT(lrd::test::translation_error(d->T_cw_corrected, LoopScene::true_pose(3)), 0.003);
  EXPECT_LT(lrd::test::rotation_error_deg(d->T_cw_corrected, LoopScene::true_pose(3)), 0.1);
  // ... far from where odometry put it.
  EXPECT_GT(lrd::test::translation_error(s.back[3]->T_cw(), LoopScene::true_pose(3)), 0.3);
  EXPECT_GE(d->ransac_inliers, 20);
  EXPECT_GE(d->match_count, 40);
  EXPECT_GE(d->match_count, d->ransac_inliers);
  // The matches: one slot per keypoint, each a point of the first visit, seen from the corrected
  // pose on its keypoint (the views are the same images).
  ASSERT_EQ(d->matches.size(), s.back[3]->size());
  EXPECT_EQ(static_cast<int>(
                std::count_if(d->matches.begin(), d->matches.end(), [](auto* p) { return p != nullptr; })),
            d->match_count);
  const auto& cam = s.back[3]->features().camera();
  int on_keypoint = 0;
  for (std::size_t i = 0; i < d->matches.size(); ++i) {
    const MapPoint* mp = d->matches[i];
    if (mp == nullptr) continue;
    EXPECT_NE(std::find(s.first_points.begin(), s.first_points.end(), mp), s.first_points.end());
    const Eigen::Vector2d uv = cam.project(d->T_cw_corrected * mp->position());
    const cv::Point2f& kp = s.back[3]->features().undistorted()[i].pt;
    on_keypoint += (uv - Eigen::Vector2d(kp.x, kp.y)).norm() < 2.0;
  }
  EXPECT_GE(on_keypoint, 0.9 * d->match_count);
  // The loop side's neighbourhood: every good point of the first visit.
  std::vector<MapPoint*> expected;
  for (MapPoint* mp : s.first_points)
    if (!mp->is_bad()) expected.push_back(mp);
  std::sort(expected.begin(), expected.end(), lrd::map::ById{});
  EXPECT_EQ(d->loop_points, expected);
}

TEST(LoopDetector, AKeyFrameWithoutCandidatesBreaksTheChain) {
  lrd::map::KeyFrameDatabase db;
  LoopScene s(&db);
  s.add_first_visit();
  s.add_second_visit(0, 2);
  const auto elsewhere = s.add_elsewhere();  // in between: a place never seen before
  s.add_second_visit(2, 4);
  assert_candidates(s, db);
  ASSERT_FALSE(elsewhere[0]->ordered_covisibles().empty());
  // Its neighbour is the same view: nothing scores as high as that.
  const double own = lrd::place::Vocabulary::score(elsewhere[0]->bow(), elsewhere[1]->bow());
  ASSERT_TRUE(db.loop_candidates(elsewhere[0], own).empty());

  LoopDetector detector(db, LoopDetectorParams{});
  EXPECT_FALSE(detector.detect(s.back[0]));
  EXPECT_FALSE(detector.detect(s.back[1]));
  EXPECT_FALSE(detector.detect(elsewhere[0]));  // resets the consistent groups
  EXPECT_FALSE(detector.detect(s.back[2]));     // would have been the third in a row ...
  EXPECT_FALSE(detector.detect(s.back[3]));     // ... and this the fourth: a loop
}

TEST(LoopDetector, AfterALoopTheNextWaitsAndStartsAfresh) {
  lrd::map::KeyFrameDatabase db;
  LoopScene s(&db);
  s.add_first_visit();
  s.add_second_visit();
  LoopDetectorParams params;
  params.consistency = 1;  // a candidate group seen by two consecutive keyframes
  params.min_keyframes_between = 2;
  LoopDetector closing(db, params), control(db, params);

  EXPECT_FALSE(closing.detect(s.back[0]));
  const auto d = closing.detect(s.back[1]);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->loop, s.first[1]);
  closing.loop_closed(s.back[1]);
  EXPECT_FALSE(closing.detect(s.back[2]));  // within 2 keyframes of the last loop
  EXPECT_FALSE(closing.detect(s.back[3]));  // allowed again, but its group starts at 0

  // Without loop_closed() the same keyframes keep closing loops.
  EXPECT_FALSE(control.detect(s.back[0]));
  ASSERT_TRUE(control.detect(s.back[1]));
  const auto d2 = control.detect(s.back[2]);
  ASSERT_TRUE(d2);
  EXPECT_EQ(d2->loop, s.first[2]);
  const auto d3 = control.detect(s.back[3]);
  ASSERT_TRUE(d3);
  EXPECT_EQ(d3->loop, s.first[3]);
}

TEST(LoopDetector, ALookAlikeWithOtherStructureIsNoLoop) {
  // The second visit's map points swap positions at random: the same images and words (so the
  // same candidates, consistent as before), but no rigid motion maps one visit's points onto the
  // other's.
  lrd::map::KeyFrameDatabase db;
  LoopScene s(&db);
  s.add_first_visit();
  s.add_second_visit();
  std::vector<Eigen::Vector3d> positions;
  for (const MapPoint* mp : s.back_points) positions.push_back(mp->position());
  std::mt19937 rng(3);
  std::shuffle(positions.begin(), positions.end(), rng);
  for (std::size_t i = 0; i < s.back_points.size(); ++i) s.back_points[i]->set_position(positions[i]);
  assert_candidates(s, db);

  LoopDetector detector(db, LoopDetectorParams{});
  for (KeyFrame* kf : s.back) EXPECT_FALSE(detector.detect(kf)) << kf->id();
}
