// Dilating a dynamic mask by a disc and carrying an older mask over to the current frame at half
// resolution (the asynchronous segmentation's masks; mask carry-over in
// bench/results/performance.md): exact where they promise it, covering the exact result where they
// work coarser.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/dynamic/mask_propagator.h"

// A named namespace: the test preset builds several test files as one (unity build).
namespace mask_carry {

const lrd::camera::PinholeCamera& tum3() {
  static const lrd::camera::PinholeCamera cam = lrd::camera::camera_preset("tum3");
  return cam;
}

// The disc of dilate_mask's contract as a structuring element: du^2 + dv^2 <= r^2.
cv::Mat disc(int r) {
  cv::Mat k = cv::Mat::zeros(2 * r + 1, 2 * r + 1, CV_8U);
  for (int v = -r; v <= r; ++v)
    for (int u = -r; u <= r; ++u)
      if (u * u + v * v <= r * r) k.at<std::uint8_t>(v + r, u + r) = 1;
  return k;
}

// People-like blobs (ellipses), a few scattered pixels and a run touching the border.
cv::Mat blobs(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(0, 639), y(0, 479), axis(5, 90);
  cv::Mat mask = cv::Mat::zeros(480, 640, CV_8UC1);
  for (int i = 0; i < 4; ++i)
    cv::ellipse(mask, cv::Point(x(rng), y(rng)), cv::Size(axis(rng), axis(rng)), 0.0, 0.0, 360.0, 255, -1);
  for (int i = 0; i < 20; ++i) mask.at<std::uint8_t>(y(rng), x(rng)) = 7;  // any nonzero value
  mask(cv::Rect(600, 0, 40, 30)).setTo(255);
  return mask;
}

int outside(const cv::Mat& a, const cv::Mat& b) {  // pixels set in a and not in b
  return cv::countNonZero((a != 0) & (b == 0));
}

}  // namespace mask_carry

TEST(MaskCarry, DilationIsExactlyTheDiscAtEveryRadius) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const cv::Mat mask = mask_carry::blobs(seed);
    for (const int radius : {1, 2, 5, 7, 11, 20, 31}) {
      SCOPED_TRACE(testing::Message() << "seed " << seed << " radius " << radius);
      cv::Mat reference;
      cv::dilate(mask != 0, reference, mask_carry::disc(radius), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT,
                 0);
      cv::Mat ours = mask.clone();
      const cv::Mat alias = ours;  // in place: another header on the buffer sees the result
      lrd::dynamic::dilate_mask(ours, radius);
      ASSERT_EQ(ours.type(), CV_8UC1);
      EXPECT_EQ(cv::countNonZero(ours != reference), 0);
      EXPECT_EQ(alias.data, ours.data);
    }
  }
}

TEST(MaskCarry, BelowTheHalfResolutionRadiusCarryingIsPropagationThenDilation) {
  const auto& cam = mask_carry::tum3();
  const cv::Mat mask = mask_carry::blobs(4), depth(480, 640, CV_32F, cv::Scalar(2.0f));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.05, -0.02, 0.03);
  cv::Mat exact = lrd::dynamic::propagate_mask(mask, depth, T, cam);
  lrd::dynamic::dilate_mask(exact, lrd::dynamic::kHalfResolutionRadius - 1);
  const cv::Mat carried =
      lrd::dynamic::carry_mask(mask, depth, T, cam, lrd::dynamic::kHalfResolutionRadius - 1);
  EXPECT_EQ(cv::countNonZero(carried != exact), 0);
}

// From kHalfResolutionRadius on: every pixel of the exact result is covered, and nothing lies more
// than a few pixels beyond where the mask's pixels or their neighbours go, for motions sideways, towards and
// away, turning, with depth that varies (a slanted scene) and holes without depth (which stay where they
// were).
TEST(MaskCarry, AtHalfResolutionTheExactResultIsCoveredWithinAFewPixels) {
  const auto& cam = mask_carry::tum3();
  cv::Mat depth(480, 640, CV_32F);
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u)
      depth.at<float>(v, u) = static_cast<float>(1.2 + 0.003 * u + 0.001 * v);
  depth(cv::Rect(100, 100, 60, 50)).setTo(0.0f);
  std::vector<Eigen::Isometry3d> motions(4, Eigen::Isometry3d::Identity());
  motions[1].translation() = Eigen::Vector3d(0.08, 0.03, 0.0);
  motions[2].translation() = Eigen::Vector3d(0.0, 0.0, 0.25);  // 25 cm closer: the mask grows
  motions[3].linear() =
      Eigen::AngleAxisd(0.06, Eigen::Vector3d(0.3, 1.0, 0.2).normalized()).toRotationMatrix();
  motions[3].translation() = Eigen::Vector3d(-0.04, 0.0, -0.1);
  for (unsigned seed = 5; seed <= 7; ++seed) {
    cv::Mat mask = mask_carry::blobs(seed);
    cv::ellipse(mask, cv::Point(130, 125), cv::Size(40, 30), 0.0, 0.0, 360.0, 255,
                -1);  // partly without depth
    for (std::size_t m = 0; m < motions.size(); ++m)
      for (const int radius : {9, 11, 19}) {
        SCOPED_TRACE(testing::Message() << "seed " << seed << " motion " << m << " radius " << radius);
        cv::Mat exact = lrd::dynamic::propagate_mask(mask, depth, motions[m], cam);
        lrd::dynamic::dilate_mask(exact, radius);
        // Where the mask's pixels and their neighbours (a 2x2 block moves as one) would go, grown
        // by the radius and 7 pixels more.
        cv::Mat near = mask.clone();
        lrd::dynamic::dilate_mask(near, 2);
        cv::Mat generous = lrd::dynamic::propagate_mask(near, depth, motions[m], cam);
        lrd::dynamic::dilate_mask(generous, radius + 7);
        const cv::Mat carried = lrd::dynamic::carry_mask(mask, depth, motions[m], cam, radius);
        ASSERT_EQ(carried.type(), CV_8UC1);
        ASSERT_EQ(carried.size(), mask.size());
        EXPECT_EQ(mask_carry::outside(exact, carried), 0);
        EXPECT_EQ(mask_carry::outside(carried, generous), 0);
        EXPECT_LT(cv::countNonZero(carried), 1.5 * cv::countNonZero(exact));
      }
  }
}

// An image of odd width and height (the last blocks are one pixel wide or tall, and the last
// column and row must still be carried), and a frame without depth (every block stays where it
// was): the exact result is still covered, within a few pixels.
TEST(MaskCarry, OddSizesAndFramesWithoutDepthAreCoveredToo) {
  const auto& cam = mask_carry::tum3();
  const cv::Mat mask = mask_carry::blobs(8)(cv::Rect(319, 0, 321, 241)).clone();  // the border run included
  cv::Mat depth(mask.size(), CV_32F, cv::Scalar(1.5f));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.03, -0.02, 0.05);
  for (const bool with_depth : {true, false}) {
    const cv::Mat d = with_depth ? depth : cv::Mat();
    for (const int radius : {9, 13}) {
      SCOPED_TRACE(testing::Message() << "depth " << with_depth << " radius " << radius);
      cv::Mat exact = lrd::dynamic::propagate_mask(mask, d, T, cam);
      lrd::dynamic::dilate_mask(exact, radius);
      cv::Mat near = mask.clone();
      lrd::dynamic::dilate_mask(near, 2);
      cv::Mat generous = lrd::dynamic::propagate_mask(near, d, T, cam);
      lrd::dynamic::dilate_mask(generous, radius + 7);
      const cv::Mat carried = lrd::dynamic::carry_mask(mask, d, T, cam, radius);
      ASSERT_EQ(carried.size(), mask.size());
      EXPECT_GT(cv::countNonZero(exact), 1000);
      EXPECT_EQ(mask_carry::outside(exact, carried), 0);
      EXPECT_EQ(mask_carry::outside(carried, generous), 0);
      // The border run (top right) still reaches the last column (moved right, or staying).
      EXPECT_NE(carried.at<std::uint8_t>(0, mask.cols - 1), 0);
    }
  }
}
