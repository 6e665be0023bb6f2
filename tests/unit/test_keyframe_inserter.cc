// The keyframe decision's close-points rule (ORB-SLAM2's bNeedToInsertClose, our
// tracking.keyframe_close_tracked / keyframe_close_untracked): on a view of the textured plane
// whose close keypoints are partly tracked, a keyframe is asked for exactly when fewer than
// keyframe_close_tracked of them are tracked and more than keyframe_close_untracked are not —
// both bounds strict — and never with 15 inliers or fewer. The other rules stay silent: pose
// optimization is said to keep as many inliers as the reference keyframe tracks (the reference
// ratio holds), coverage is off, and frame 1 is far from the camera's fps frames since the last
// keyframe.
#include <gtest/gtest.h>

#include <cstddef>

#include "lrd/mapping/local_mapper.h"
#include "lrd/tracking/keyframe_inserter.h"
#include "map_scene.h"

using lrd::tracking::KeyFrameContext;
using lrd::tracking::KeyFrameInserter;
using lrd::tracking::TrackerParams;

namespace keyframe_inserter_test {

struct CloseCounts {
  int tracked = 0, untracked = 0;
};

CloseCounts count_close(const lrd::data::Frame& f) {
  CloseCounts c;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!f.is_close(i)) continue;
    (f.map_points[i] != nullptr && !f.outliers[i] ? c.tracked : c.untracked)++;
  }
  return c;
}

// Keyframe 0 maps every keypoint with depth; frame 1, from the same pose, keeps `tracked` of its
// close matches to them and loses the rest.
struct PartlyTrackedView {
  lrd::test::TexturedPlane plane;
  lrd::map::Map map;
  lrd::mapping::LocalMapper mapper{map, lrd::mapping::LocalMapperParams{}, /*threaded=*/false};
  lrd::map::KeyFrame* kf0 = nullptr;
  lrd::data::Frame frame;
  CloseCounts close;

  explicit PartlyTrackedView(int tracked) : frame(plane.frame(1, Eigen::Isometry3d::Identity())) {
    kf0 = lrd::test::keyframe_with_points(map, plane.frame(0, Eigen::Isometry3d::Identity()));
    lrd::test::associate(frame, lrd::test::points_of(kf0));
    int kept = 0;
    for (std::size_t i = 0; i < frame.size(); ++i) {
      if (frame.map_points[i] == nullptr) continue;
      if (frame.is_close(i) && kept < tracked)
        ++kept;
      else if (frame.is_close(i))
        frame.map_points[i] = nullptr;
    }
    close = count_close(frame);
  }

  // `inliers`: pose optimization's (default: the reference keyframe's tracked points).
  [[nodiscard]] bool needed(const TrackerParams& params, int inliers = -1) {
    const KeyFrameInserter inserter(map, mapper, params);
    if (inliers < 0) inliers = kf0->tracked_map_points(1);
    return inserter.needed(frame, KeyFrameContext{kf0, inliers, std::nullopt});
  }
};

TrackerParams close_rule(int tracked, int untracked) {
  TrackerParams p;
  p.keyframe_coverage = 0.0;
  p.keyframe_close_tracked = tracked;
  p.keyframe_close_untracked = untracked;
  return p;
}

}  // namespace keyframe_inserter_test

using keyframe_inserter_test::close_rule;
using keyframe_inserter_test::PartlyTrackedView;

TEST(KeyFrameInserter, CloseRuleAsksWhenFewTrackedAndManyUntracked) {
  PartlyTrackedView view(60);
  const int t = view.close.tracked, u = view.close.untracked;
  ASSERT_EQ(t, 60);
  ASSERT_GT(u, 200) << "the plane's close keypoints the frame lost";
  EXPECT_TRUE(view.needed(close_rule(t + 1, u - 1)));
  EXPECT_TRUE(view.needed(close_rule(100, 70))) << "ORB-SLAM2's values";
  EXPECT_FALSE(view.needed(close_rule(t, u - 1))) << "tracked close points: strictly fewer";
  EXPECT_FALSE(view.needed(close_rule(t + 1, u))) << "untracked close points: strictly more";
  EXPECT_FALSE(view.needed(close_rule(50, 70))) << "60 tracked close points are enough at 50";
  EXPECT_FALSE(view.needed(close_rule(t + 1, u - 1), 15)) << "no keyframe from 15 inliers";
}

TEST(KeyFrameInserter, NoCloseRuleKeyframeWhileTrackingEnoughClosePoints) {
  PartlyTrackedView view(150);
  ASSERT_EQ(view.close.tracked, 150);
  ASSERT_GT(view.close.untracked, 70);
  EXPECT_FALSE(view.needed(close_rule(100, 70)));
  EXPECT_TRUE(view.needed(close_rule(151, 70)));
}
