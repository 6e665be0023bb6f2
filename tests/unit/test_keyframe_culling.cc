// Keyframe culling's two rules (mapping/keyframe_culling.h) on keyframes of the textured plane:
// ORB-SLAM2's (90 % of the close points seen by three others) and the place rule for a camera that
// comes back — a revisit keyframe at the place of a keyframe made ten or more keyframes before it
// goes when half its points are seen by three others, but not while it is among the last ten
// keyframes made, not from another place (baseline over 4.5 % of the scene depth, or the view turned
// by over 7 degrees), and not when too few of its points are known.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "lrd/mapping/keyframe_culling.h"
#include "map_scene.h"

using lrd::data::Frame;
using lrd::map::KeyFrame;
using lrd::map::MapPoint;
using lrd::mapping::CullingDecision;
using lrd::mapping::judge_redundancy;
using lrd::mapping::KeyFrameCullingParams;

namespace keyframe_culling_test {

// Four keyframes of the view from the identity pose: the first makes a point for every keypoint
// with depth, the next three match them all. Then a revisit keyframe of the same view that matches
// one in `keep_one_in` of those points (or all but one in `skip_one_in`) and, as tracking does,
// makes its own points for the keypoints it did not match (scale.md, walking_circle: the
// background seen between people), placed at `T_cw`.
struct Revisit {
  lrd::test::TexturedPlane plane;
  lrd::map::Map map;
  std::vector<KeyFrame*> first;
  KeyFrame* revisit = nullptr;
  int matched = 0;  // of the revisit's points, the first keyframes'
  int own = 0;      // made by the revisit

  Revisit(const Eigen::Isometry3d& T_cw, int keep_one_in, int skip_one_in = 0) {
    const Frame view = plane.frame(0, Eigen::Isometry3d::Identity());
    first.push_back(lrd::test::keyframe_with_points(map, view));
    const std::vector<MapPoint*> points = lrd::test::points_of(first[0]);
    for (int k = 1; k <= 3; ++k) {
      Frame f = view;
      (void)lrd::test::associate(f, points);
      first.push_back(lrd::test::tracking_keyframe(map, f));
      lrd::test::register_keyframe(first.back());
    }
    // The keyframes made while the camera was away (sharing nothing with these): the revisit is
    // ten keyframes after the last of the first four.
    for (int k = 0; k < 9; ++k) (void)map.create_keyframe(view);
    std::vector<MapPoint*> known;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const bool keep = keep_one_in > 0 && i % static_cast<std::size_t>(keep_one_in) == 0;
      const bool skip = skip_one_in > 0 && i % static_cast<std::size_t>(skip_one_in) == 0;
      if (keep || (keep_one_in == 0 && !skip)) known.push_back(points[i]);
    }
    Frame f = view;
    (void)lrd::test::associate(f, known);
    revisit = lrd::test::tracking_keyframe(map, f);
    lrd::test::register_keyframe(revisit);
    // The rule reads the keyframe's pose, not its image: the same view, placed at T_cw.
    revisit->set_pose(T_cw);
    for (const MapPoint* mp : lrd::test::points_of(revisit)) {
      matched += mp->is_in_keyframe(first[0]) ? 1 : 0;
      own += mp->reference_keyframe() == revisit ? 1 : 0;
    }
  }
  [[nodiscard]] double share() const { return double(matched) / (matched + own); }
  // Judged while the keyframe `after` ids later is mapped.
  [[nodiscard]] CullingDecision judge(std::uint64_t after, const KeyFrameCullingParams& p = {}) const {
    return judge_redundancy(*revisit, revisit->id() + after, p);
  }
};

// A revisit from the same place that knows two thirds of what it sees (every point but each third).
TEST(KeyFrameCulling, ARevisitAtAnOlderKeyFramesPlaceGoesOnceTheCameraHasLeft) {
  const Revisit r(Eigen::Isometry3d::Identity(), 0, 3);
  ASSERT_GT(r.matched, 300);
  ASSERT_GT(r.share(), 0.6);
  ASSERT_LT(r.share(), 0.7);
  // Every point lies within the close depth (2.2 m plane): each counts.
  const CullingDecision d = r.judge(10);
  EXPECT_EQ(d.points.close_points, r.matched + r.own);
  EXPECT_EQ(d.points.redundant, r.matched);  // seen by four others; its own points by none
  EXPECT_TRUE(d.cull);
  ASSERT_NE(d.same_place, nullptr);
  EXPECT_LT(d.same_place->id(), r.revisit->id());
  // While it is among the last ten keyframes made, it stays.
  EXPECT_FALSE(r.judge(9).cull);
  // And it is no revisit when the keyframes at its place are not ten older than it: the camera
  // stayed (ORB-SLAM2's rule alone judges the keyframes of a camera hovering in one place).
  // (The first four are 13 to 10 keyframes older.)
  ASSERT_EQ(r.revisit->id(), r.first[0]->id() + 13);
  KeyFrameCullingParams apart;
  apart.place_keyframes_apart = 14;
  EXPECT_FALSE(r.judge(14, apart).cull);
  apart.place_keyframes_apart = 13;
  const CullingDecision oldest = r.judge(14, apart);
  EXPECT_TRUE(oldest.cull);
  EXPECT_EQ(oldest.same_place, r.first[0]);
  // ORB-SLAM2's rule alone keeps it (two thirds < 90 %).
  KeyFrameCullingParams orb;
  orb.place_redundant_ratio = 0.0;
  const CullingDecision by_points = r.judge(10, orb);
  EXPECT_FALSE(by_points.cull);
  EXPECT_EQ(by_points.same_place, nullptr);
}

// Knowing every point, ORB-SLAM2's rule decides, at any age, without the place.
TEST(KeyFrameCulling, AKeyFrameWhosePointsOthersSeeGoesByORBSLAM2sRule) {
  const Revisit r(Eigen::Isometry3d::Identity(), 1);
  ASSERT_GT(r.share(), 0.9);
  const CullingDecision d = r.judge(1);
  EXPECT_TRUE(d.cull);
  EXPECT_EQ(d.same_place, nullptr);
}

TEST(KeyFrameCulling, ARevisitKnowingTooLittleStays) {
  const Revisit r(Eigen::Isometry3d::Identity(), 3);  // a third of the points
  ASSERT_LT(r.share(), 0.45);
  const CullingDecision d = r.judge(10);
  EXPECT_FALSE(d.cull);
  EXPECT_EQ(d.points.redundant, r.matched);
}

// The place: within 4.5 % of the median scene depth (2.2 m: 9.9 cm) and 7 degrees.
TEST(KeyFrameCulling, OnlyAKeyFrameAtTheSamePlaceIsARevisit) {
  using lrd::test::pose;
  const double deg = M_PI / 180.0;
  const Revisit near(pose(0.0, 5.0 * deg, 0.0, -0.07, 0.0, 0.0), 0, 3);  // 7 cm, 5 degrees
  ASSERT_GT(near.share(), 0.5);
  EXPECT_TRUE(near.judge(10).cull);
  EXPECT_NE(near.judge(10).same_place, nullptr);

  const Revisit aside(pose(0.0, 0.0, 0.0, -0.12, 0.0, 0.0), 0, 3);  // 12 cm
  ASSERT_GT(aside.share(), 0.5);
  EXPECT_FALSE(aside.judge(10).cull);
  KeyFrameCullingParams wider;  // the same keyframe with a looser place
  wider.place_baseline_ratio = 0.06;
  EXPECT_TRUE(aside.judge(10, wider).cull);

  const Revisit turned(pose(0.0, 9.0 * deg, 0.0, 0.0, 0.0, 0.0), 0, 3);  // 9 degrees
  ASSERT_GT(turned.share(), 0.5);
  EXPECT_FALSE(turned.judge(10).cull);
  wider.place_angle_deg = 10.0;
  EXPECT_TRUE(turned.judge(10, wider).cull);
}

}  // namespace keyframe_culling_test
