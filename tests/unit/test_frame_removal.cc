// Dropping dynamic keypoints after extraction (Frame::remove_keypoints) and the two-phase ORB
// extraction (detect() while the mask is computed, describe_detected() once it is there).
#include <gtest/gtest.h>

#include <cstring>
#include <opencv2/imgproc.hpp>
#include <set>
#include <tuple>
#include <vector>

#include "lrd/data/frame.h"
#include "lrd/features/orb_extractor.h"
#include "lrd/map/map.h"
#include "lrd/util/error.h"
#include "textured_plane.h"

using lrd::features::OrbExtractor;
using lrd::features::OrbParams;

namespace {

bool same_keypoint(const cv::KeyPoint& a, const cv::KeyPoint& b) {
  return a.pt == b.pt && a.size == b.size && a.angle == b.angle && a.response == b.response &&
         a.octave == b.octave;
}

bool same_row(const cv::Mat& a, int i, const cv::Mat& b, int j) {
  return std::memcmp(a.ptr(i), b.ptr(j), static_cast<std::size_t>(a.cols)) == 0;
}

// A view of the textured plane with a mask over a disc and a band (about a fifth of the image).
struct Scene {
  lrd::test::TexturedPlane plane{7};
  Eigen::Isometry3d T_cw = lrd::test::pose(0.02, -0.03, 0.01, 0.05, -0.02, 0.1);
  lrd::test::TexturedPlane::Image image = plane.render(T_cw);
  cv::Mat mask = [] {
    cv::Mat m = cv::Mat::zeros(480, 640, CV_8U);
    cv::circle(m, cv::Point(200, 220), 90, cv::Scalar(255), cv::FILLED);
    m(cv::Rect(420, 0, 80, 480)).setTo(7);  // any nonzero value masks
    return m;
  }();
};

}  // namespace

TEST(FrameRemoval, RemoveKeypointsKeepsEverythingAligned) {
  Scene s;
  lrd::data::Frame frame = s.plane.frame(3, s.T_cw);
  const std::size_t n = frame.size();
  ASSERT_GT(n, 800u);
  // Real map points for the keypoints with depth, and some outlier flags, as tracking leaves them.
  lrd::map::Map map;
  const lrd::map::KeyFrame* kf = lrd::test::keyframe_with_points(map, frame);
  for (std::size_t i = 0; i < n; ++i) {
    frame.map_points[i] = kf->map_point(i);
    frame.outliers[i] = i % 5 == 0;
  }
  // Drop a pattern plus a block, then remember what the kept ones were.
  std::vector<bool> drop(n);
  for (std::size_t i = 0; i < n; ++i) drop[i] = i % 3 == 1 || (i >= 100 && i < 160);
  drop[0] = true;
  drop[n - 1] = true;
  const std::vector<cv::KeyPoint> kps = frame.keypoints(), und = frame.undistorted();
  const cv::Mat desc = frame.descriptors().clone();
  std::vector<float> depth(n), u_right(n);
  for (std::size_t i = 0; i < n; ++i) depth[i] = frame.depth(i), u_right[i] = frame.u_right(i);
  const auto points = frame.map_points;
  const auto outliers = frame.outliers;

  frame.remove_keypoints(drop);
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i)
    if (!drop[i]) kept.push_back(i);
  ASSERT_EQ(frame.size(), kept.size());
  ASSERT_EQ(frame.undistorted().size(), kept.size());
  ASSERT_EQ(frame.descriptors().rows, static_cast<int>(kept.size()));
  ASSERT_EQ(frame.descriptors().cols, 32);
  ASSERT_EQ(frame.map_points.size(), kept.size());
  ASSERT_EQ(frame.outliers.size(), kept.size());
  int with_point = 0;
  for (std::size_t j = 0; j < kept.size(); ++j) {
    const std::size_t i = kept[j];
    EXPECT_TRUE(same_keypoint(frame.keypoints()[j], kps[i])) << j;
    EXPECT_TRUE(same_keypoint(frame.undistorted()[j], und[i])) << j;
    EXPECT_TRUE(same_row(frame.descriptors(), static_cast<int>(j), desc, static_cast<int>(i))) << j;
    EXPECT_EQ(frame.depth(j), depth[i]) << j;
    EXPECT_EQ(frame.u_right(j), u_right[i]) << j;
    EXPECT_EQ(frame.map_points[j], points[i]) << j;
    EXPECT_EQ(frame.outliers[j], outliers[i]) << j;
    with_point += frame.map_points[j] != nullptr;
  }
  EXPECT_GT(with_point, static_cast<int>(kept.size() / 2));

  // The grid holds exactly the kept keypoints, under their new indices.
  const cv::Rect2f b = frame.bounds();
  const auto all = frame.features_in_area(b.x + b.width / 2, b.y + b.height / 2, 2 * (b.width + b.height));
  ASSERT_EQ(all.size(), kept.size());
  for (std::size_t j = 0; j < all.size(); ++j) EXPECT_EQ(all[j], j);
  for (std::size_t i = 0; i < n; ++i) {
    const auto near = frame.features_in_area(und[i].pt.x, und[i].pt.y, 0.5f);
    bool found = false;
    for (std::size_t j : near) found = found || same_keypoint(frame.undistorted()[j], und[i]);
    EXPECT_EQ(found, !drop[i]) << "keypoint " << i;
  }
}

TEST(FrameRemoval, DropNothingOrEverything) {
  Scene s;
  lrd::data::Frame frame = s.plane.frame(4, s.T_cw);
  const std::size_t n = frame.size();
  const std::vector<cv::KeyPoint> kps = frame.keypoints();
  const cv::Mat desc = frame.descriptors().clone();
  frame.remove_keypoints(std::vector<bool>(n, false));
  ASSERT_EQ(frame.size(), n);
  for (std::size_t i = 0; i < n; ++i) EXPECT_TRUE(same_keypoint(frame.keypoints()[i], kps[i]));
  EXPECT_EQ(cv::norm(frame.descriptors(), desc, cv::NORM_HAMMING), 0.0);
  EXPECT_EQ(frame.features_in_area(320, 240, 1000).size(), n);

  frame.remove_keypoints(std::vector<bool>(n, true));
  EXPECT_EQ(frame.size(), 0u);
  EXPECT_EQ(frame.descriptors().rows, 0);
  EXPECT_TRUE(frame.map_points.empty());
  EXPECT_TRUE(frame.outliers.empty());
  EXPECT_TRUE(frame.features_in_area(320, 240, 1000).empty());
}

TEST(OrbTwoPhase, DescribeDetectedWithoutMaskEqualsExtract) {
  Scene s;
  OrbExtractor a{OrbParams{}}, b{OrbParams{}};
  std::vector<cv::KeyPoint> ka, kb;
  cv::Mat da, db;
  a.extract(s.image.grey, cv::Mat(), ka, da);
  b.detect(s.image.grey);
  b.describe_detected(cv::Mat(), kb, db);
  ASSERT_GT(ka.size(), 800u);
  ASSERT_EQ(ka.size(), kb.size());
  ASSERT_EQ(da.rows, db.rows);
  for (std::size_t i = 0; i < ka.size(); ++i) {
    EXPECT_TRUE(same_keypoint(ka[i], kb[i])) << i;
    EXPECT_TRUE(same_row(da, static_cast<int>(i), db, static_cast<int>(i))) << i;
  }
  // The same extractor can do both in turn.
  std::vector<cv::KeyPoint> kc;
  cv::Mat dc;
  a.detect(s.image.grey);
  a.describe_detected(cv::Mat(), kc, dc);
  ASSERT_EQ(kc.size(), ka.size());
  EXPECT_EQ(cv::norm(dc, da, cv::NORM_HAMMING), 0.0);
}

TEST(OrbTwoPhase, MaskGivenAfterDetection) {
  Scene s;
  OrbExtractor a{OrbParams{}}, b{OrbParams{}};
  std::vector<cv::KeyPoint> ka, kb;
  cv::Mat da, db;
  a.extract(s.image.grey, s.mask, ka, da);
  b.detect(s.image.grey);
  b.describe_detected(s.mask, kb, db);
  ASSERT_EQ(static_cast<int>(kb.size()), db.rows);
  for (const cv::KeyPoint& kp : kb) {
    const int u = cvRound(kp.pt.x), v = cvRound(kp.pt.y);
    ASSERT_TRUE(u >= 0 && v >= 0 && u < 640 && v < 480);
    EXPECT_EQ(s.mask.at<std::uint8_t>(v, u), 0) << kp.pt;
  }
  for (const cv::KeyPoint& kp : ka) EXPECT_EQ(s.mask.at<std::uint8_t>(cvRound(kp.pt.y), cvRound(kp.pt.x)), 0);
  ASSERT_GT(ka.size(), 700u);
  EXPECT_NEAR(static_cast<double>(kb.size()), static_cast<double>(ka.size()),
              0.1 * static_cast<double>(ka.size()));
  // The budget goes to the rest of the image: about as many as without the mask.
  EXPECT_GT(kb.size(), 0.9 * OrbParams{}.n_features);
  // Most keypoints are the same ones (the two differ only where a cell's strong corners are all masked).
  std::set<std::tuple<float, float, int>> in_a;
  for (const cv::KeyPoint& kp : ka) in_a.emplace(kp.pt.x, kp.pt.y, kp.octave);
  std::size_t common = 0;
  for (const cv::KeyPoint& kp : kb) common += in_a.count({kp.pt.x, kp.pt.y, kp.octave});
  EXPECT_GT(common, 0.7 * static_cast<double>(kb.size()));

  // A frame built from the detected corners equals one extracted in full, mask and all.
  const lrd::features::KeypointUndistorter undistorter(s.plane.camera());
  const lrd::data::Frame full(1, 0.0, s.image.grey, s.image.depth, s.mask, a, undistorter, s.plane.camera());
  b.detect(s.image.grey);
  const lrd::data::Frame two_phase(1, 0.0, s.image.grey, s.image.depth, s.mask, b, undistorter,
                                   s.plane.camera(), lrd::data::Frame::Extraction::DescribeDetected);
  EXPECT_EQ(two_phase.size(), kb.size());
  EXPECT_EQ(full.size(), ka.size());
  EXPECT_EQ(cv::norm(two_phase.descriptors(), db, cv::NORM_HAMMING), 0.0);
  EXPECT_EQ(cv::countNonZero(two_phase.dynamic_mask != s.mask), 0);
}

TEST(OrbTwoPhase, WholeImageMaskedGivesNoKeypoints) {
  Scene s;
  OrbExtractor b{OrbParams{}};
  std::vector<cv::KeyPoint> kb;
  cv::Mat db;
  b.detect(s.image.grey);
  b.describe_detected(cv::Mat(480, 640, CV_8U, cv::Scalar(255)), kb, db);
  EXPECT_TRUE(kb.empty());
  EXPECT_EQ(db.rows, 0);
  // A mask of the wrong size is refused.
  b.detect(s.image.grey);
  EXPECT_THROW(b.describe_detected(cv::Mat(240, 320, CV_8U, cv::Scalar(0)), kb, db), lrd::Error);
  EXPECT_THROW(b.describe_detected(cv::Mat(480, 640, CV_16U, cv::Scalar(0)), kb, db), lrd::Error);
}
