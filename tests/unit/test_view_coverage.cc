// The keyframe-coverage rule's measure (tracking/view_coverage.h) on a rendered textured plane:
// the share of the view the tracked keypoints span, robust to a hole in the middle (a person).
#include <gtest/gtest.h>

#include <functional>

#include "lrd/map/keyframe.h"
#include "lrd/map/map.h"
#include "lrd/tracking/view_coverage.h"
#include "textured_plane.h"

using lrd::tracking::tracked_view_coverage;

namespace {

struct Fixture {
  lrd::test::TexturedPlane scene;
  lrd::map::Map map;
  lrd::data::Frame frame = scene.frame(0, Eigen::Isometry3d::Identity());
  lrd::map::MapPoint* point = nullptr;

  Fixture() {
    lrd::map::KeyFrame* kf = map.create_keyframe(frame);
    point = map.create_map_point(Eigen::Vector3d(0, 0, 2), kf, 0);
  }
  // Tracks (gives a map point to) the keypoints whose position passes `tracked`.
  void track(const std::function<bool(const cv::Point2f&)>& tracked) {
    for (std::size_t i = 0; i < frame.size(); ++i) {
      frame.map_points[i] = tracked(frame.undistorted()[i].pt) ? point : nullptr;
      frame.outliers[i] = false;
    }
  }
};

}  // namespace

TEST(ViewCoverage, WholeViewTrackedIsOne) {
  Fixture f;
  ASSERT_GT(f.frame.size(), 500u);
  f.track([](const cv::Point2f&) { return true; });
  EXPECT_NEAR(tracked_view_coverage(f.frame), 1.0, 1e-9);
}

TEST(ViewCoverage, OneStripIsItsShareOfTheView) {
  Fixture f;
  // Columns 420-570 of a 640-wide view (keypoints span ~20-620): about a quarter.
  f.track([](const cv::Point2f& p) { return p.x >= 420 && p.x <= 570; });
  const double c = tracked_view_coverage(f.frame);
  EXPECT_GT(c, 0.15);
  EXPECT_LT(c, 0.3);
  // Rows work the same way.
  f.track([](const cv::Point2f& p) { return p.y < 160; });
  EXPECT_LT(tracked_view_coverage(f.frame), 0.4);
}

TEST(ViewCoverage, AHoleInTheMiddleLeavesTheSpan) {
  Fixture f;
  // A person in the middle third of the view: nothing tracked there, the span stays whole.
  f.track([](const cv::Point2f& p) { return p.x < 220 || p.x > 420; });
  EXPECT_GT(tracked_view_coverage(f.frame), 0.9);
}

TEST(ViewCoverage, OutliersAreNotTracked) {
  Fixture f;
  f.track([](const cv::Point2f&) { return true; });
  for (std::size_t i = 0; i < f.frame.size(); ++i) f.frame.outliers[i] = f.frame.undistorted()[i].pt.x < 420;
  EXPECT_LT(tracked_view_coverage(f.frame), 0.45);
}

TEST(ViewCoverage, TooFewTrackedIsNotJudged) {
  Fixture f;
  int n = 0;
  f.track([&n](const cv::Point2f&) { return n++ < 9; });
  EXPECT_EQ(tracked_view_coverage(f.frame), 1.0);
}

TEST(ViewCoverage, ReferencePointsUnderTheDynamicMaskAreHidden) {
  // The keyframe decision's discount (tracking.discount_hidden_points): the reference keyframe's
  // points that project onto a person in this frame.
  lrd::test::TexturedPlane scene;
  lrd::map::Map map;
  const lrd::data::Frame first = scene.frame(0, Eigen::Isometry3d::Identity());
  const lrd::map::KeyFrame* reference = lrd::test::keyframe_with_points(map, first);
  const int points = reference->tracked_map_points(1);
  ASSERT_GT(points, 500);
  // The same view with a person over its left 40 %: the points there (and only those) are hidden.
  cv::Mat person(scene.camera().height, scene.camera().width, CV_8U, cv::Scalar(0));
  person.colRange(0, 256).setTo(255);
  const lrd::data::Frame masked = scene.frame(1, Eigen::Isometry3d::Identity(), cv::Mat(), person);
  int left = 0;
  for (std::size_t i = 0; i < first.size(); ++i)
    left += reference->map_points()[i] != nullptr && first.undistorted()[i].pt.x < 255.5f ? 1 : 0;
  EXPECT_GT(left, points / 5);
  // Within rounding at the mask's edge.
  EXPECT_NEAR(lrd::tracking::reference_points_hidden(masked, *reference, 1), left, 2);
  // Points need min_observations (an RGB-D observation counts two, as in ORB-SLAM2: one keyframe
  // here); no mask, nothing hidden.
  EXPECT_EQ(lrd::tracking::reference_points_hidden(masked, *reference, 3), 0);
  EXPECT_EQ(lrd::tracking::reference_points_hidden(first, *reference, 1), 0);
}
