// Carrying an older frame's dynamic mask to the current frame (mask propagation, dilation) and
// growing flagged points into object regions on the depth image.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "lrd/camera/pinhole_camera.h"
#include "lrd/dynamic/depth_region_grower.h"
#include "lrd/dynamic/mask_propagator.h"

using lrd::dynamic::RegionGrowParams;
using lrd::dynamic::RegionSeed;

namespace {

const lrd::camera::PinholeCamera& tum3() {
  static const lrd::camera::PinholeCamera cam = lrd::camera::camera_preset("tum3");
  return cam;
}

cv::Point2d centroid(const cv::Mat& mask) {
  const cv::Moments m = cv::moments(mask, true);
  return {m.m10 / m.m00, m.m01 / m.m00};
}

}  // namespace

// --- mask propagation

TEST(MaskPropagator, IdentityMovesNothing) {
  cv::Mat mask = cv::Mat::zeros(480, 640, CV_8UC1), depth(480, 640, CV_32F, cv::Scalar(2.0f));
  mask(cv::Rect(300, 200, 40, 30)).setTo(255);
  mask(cv::Rect(100, 350, 7, 9)).setTo(1);  // any nonzero value is dynamic
  const cv::Mat out = lrd::dynamic::propagate_mask(mask, depth, Eigen::Isometry3d::Identity(), tum3());
  ASSERT_EQ(out.type(), CV_8UC1);
  ASSERT_EQ(out.size(), mask.size());
  EXPECT_EQ(cv::countNonZero(mask & ~out), 0);                             // every pixel stays set
  EXPECT_EQ(cv::countNonZero((out != 0) & (out != 255)), 0);               // 255 = dynamic
  const cv::Rect a = cv::boundingRect(out(cv::Rect(250, 150, 150, 150)));  // at most 1 px of growth
  EXPECT_EQ(a.x, 50);
  EXPECT_EQ(a.y, 50);
  EXPECT_LE(a.width, 41);
  EXPECT_LE(a.height, 31);
  const cv::Point2d before = centroid(mask(cv::Rect(250, 150, 150, 150))),
                    after = centroid(out(cv::Rect(250, 150, 150, 150)));
  EXPECT_LE(std::abs(after.x - before.x), 0.5 + 1e-9);
  EXPECT_LE(std::abs(after.y - before.y), 0.5 + 1e-9);
  EXPECT_LE(cv::countNonZero(out), 41 * 31 + 8 * 10);
}

TEST(MaskPropagator, SidewaysMotionShiftsByFocalTimesBaselineOverDepth) {
  const auto& cam = tum3();
  for (const double z : {1.5, 3.0}) {
    for (const double tx : {0.1, -0.05}) {
      SCOPED_TRACE(testing::Message() << "z " << z << " tx " << tx);
      cv::Mat mask = cv::Mat::zeros(480, 640, CV_8UC1),
              depth(480, 640, CV_32F, cv::Scalar(static_cast<float>(z)));
      mask(cv::Rect(280, 220, 50, 40)).setTo(255);
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(tx, 0.0, 0.0);
      const cv::Mat out = lrd::dynamic::propagate_mask(mask, depth, T, cam);
      const double shift = cam.fx * tx / z;
      const cv::Point2d before = centroid(mask), after = centroid(out);
      EXPECT_NEAR(after.x - before.x, shift, 1.0);
      EXPECT_NEAR(after.y - before.y, 0.0, 1.0);
      // Still one solid rectangle of about the same size (no holes from the forward warp).
      const cv::Rect r = cv::boundingRect(out);
      EXPECT_NEAR(r.width, 50, 2);
      EXPECT_NEAR(r.height, 40, 2);
      EXPECT_EQ(cv::countNonZero(out(r)), r.area());
    }
  }
}

TEST(MaskPropagator, PixelsWithoutDepthStayAndPointsBehindVanish) {
  const auto& cam = tum3();
  cv::Mat mask = cv::Mat::zeros(480, 640, CV_8UC1), depth(480, 640, CV_32F, cv::Scalar(2.0f));
  const cv::Rect no_depth(100, 100, 30, 20), with_depth(400, 300, 30, 20);
  mask(no_depth).setTo(255);
  mask(with_depth).setTo(255);
  depth(no_depth).setTo(0.0f);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.2, 0.0, 0.0);  // 53.5 px to the right at 2 m
  const cv::Mat out = lrd::dynamic::propagate_mask(mask, depth, T, cam);
  EXPECT_EQ(cv::countNonZero(out(no_depth)), no_depth.area());  // stayed
  EXPECT_EQ(cv::countNonZero(out(with_depth)), 0);              // moved away
  const cv::Rect moved = with_depth + cv::Point(static_cast<int>(std::lround(cam.fx * 0.2 / 2.0)), 0);
  EXPECT_EQ(cv::countNonZero(out(moved)), moved.area());
  EXPECT_LE(cv::countNonZero(out), 31 * 21 * 2);

  // Moving the camera 2.5 m forward puts the points behind it: nothing of them is left.
  T.translation() = Eigen::Vector3d(0.0, 0.0, -2.5);
  const cv::Mat gone = lrd::dynamic::propagate_mask(mask, depth, T, cam);
  EXPECT_EQ(cv::countNonZero(gone(cv::Rect(300, 0, 340, 480))), 0);
  EXPECT_EQ(cv::countNonZero(gone(no_depth)), no_depth.area());

  // Points that leave the image are dropped, not clamped to the border.
  T.translation() = Eigen::Vector3d(-3.0, 0.0, 0.0);
  const cv::Mat out_of_view = lrd::dynamic::propagate_mask(mask, depth, T, cam);
  EXPECT_EQ(cv::countNonZero(out_of_view(cv::Rect(0, 0, 5, 480))), 0);
  EXPECT_EQ(cv::countNonZero(out_of_view), cv::countNonZero(out_of_view(no_depth + cv::Size(1, 1))));
}

// Radii from 9 up (masks grown with age) are dilated at half resolution: the disc is covered,
// and the edge may overshoot by a few pixels (2x2 blocks, rounding).
TEST(MaskPropagator, LargeDilationCoversTheDiscWithinAFewPixels) {
  for (const int radius : {9, 11, 12, 20, 31}) {
    SCOPED_TRACE(radius);
    cv::Mat mask = cv::Mat::zeros(120, 160, CV_8UC1);
    mask.at<std::uint8_t>(60, 81) = 255;
    lrd::dynamic::dilate_mask(mask, radius);
    for (int v = 0; v < mask.rows; ++v)
      for (int u = 0; u < mask.cols; ++u) {
        const double d = std::hypot(u - 81, v - 60);
        if (d <= radius) {
          EXPECT_EQ(mask.at<std::uint8_t>(v, u), 255) << u << "," << v;
        } else if (d > radius + 6.0) {
          EXPECT_EQ(mask.at<std::uint8_t>(v, u), 0) << u << "," << v;
        }
      }
  }
}

TEST(MaskPropagator, DilateMaskGrowsByADiscOfTheRadius) {
  for (const int radius : {1, 3, 7}) {
    SCOPED_TRACE(radius);
    cv::Mat mask = cv::Mat::zeros(60, 80, CV_8UC1);
    mask.at<std::uint8_t>(30, 40) = 255;
    lrd::dynamic::dilate_mask(mask, radius);
    EXPECT_EQ(mask.at<std::uint8_t>(30, 40 + radius), 255);
    EXPECT_EQ(mask.at<std::uint8_t>(30, 40 - radius), 255);
    EXPECT_EQ(mask.at<std::uint8_t>(30 + radius, 40), 255);
    EXPECT_EQ(mask.at<std::uint8_t>(30 - radius, 40), 255);
    EXPECT_EQ(mask.at<std::uint8_t>(30, 40 + radius + 1), 0);
    EXPECT_EQ(mask.at<std::uint8_t>(30 + radius + 1, 40), 0);
    // A disc: nothing farther than the radius (plus half a pixel), corners of the square empty.
    for (int v = 0; v < mask.rows; ++v)
      for (int u = 0; u < mask.cols; ++u)
        if (mask.at<std::uint8_t>(v, u)) {
          EXPECT_LE(std::hypot(u - 40, v - 30), radius + 0.5) << u << "," << v;
        }
    const int n = cv::countNonZero(mask);
    EXPECT_GT(n, 2.5 * radius * radius);  // about pi r^2
    EXPECT_LT(n, (2 * radius + 1) * (2 * radius + 1));
  }
  cv::Mat mask = cv::Mat::zeros(20, 20, CV_8UC1);
  mask(cv::Rect(5, 5, 3, 3)).setTo(255);
  const cv::Mat before = mask.clone();
  lrd::dynamic::dilate_mask(mask, 0);
  EXPECT_EQ(cv::countNonZero(mask != before), 0);
  cv::Mat empty;
  lrd::dynamic::dilate_mask(empty, 3);
  EXPECT_TRUE(empty.empty());
}

// --- depth region growing

namespace {

// A box at 1.5 m (pixels [240, 400) x [150, 464)) standing on a floor 0.6 m below the camera,
// in front of a wall at 3 m; the floor meets the box's bottom edge and the wall, smoothly.
struct RoomDepth {
  static constexpr double kWall = 3.0, kBox = 1.5, kHeight = 0.6;
  const cv::Rect box{240, 150, 160, 314};
  cv::Mat depth = cv::Mat(480, 640, CV_32F);
  cv::Mat box_px, wall_px, floor_px;  // CV_8U masks of each surface
  RoomDepth() {
    const auto& cam = tum3();
    for (int v = 0; v < depth.rows; ++v) {
      const double floor = v > cam.cy ? kHeight * cam.fy / (v - cam.cy) : 1e9;
      for (int u = 0; u < depth.cols; ++u) depth.at<float>(v, u) = static_cast<float>(std::min(kWall, floor));
    }
    depth(box).setTo(static_cast<float>(kBox));
    box_px = cv::Mat::zeros(depth.size(), CV_8U);
    box_px(box).setTo(255);
    wall_px = (depth == static_cast<float>(kWall)) & ~box_px;
    floor_px = ~(box_px | wall_px);
  }
  // The depth the half-resolution grower saw for full-resolution pixel (u, v).
  [[nodiscard]] float sampled(int u, int v) const { return depth.at<float>(2 * (v / 2), 2 * (u / 2)); }
};

double share(const cv::Mat& grown, const cv::Mat& part) {
  return static_cast<double>(cv::countNonZero(grown & part)) / cv::countNonZero(part);
}

}  // namespace

TEST(DepthRegionGrower, GrowsOverTheObjectNotOntoTheWall) {
  const RoomDepth room;
  const auto& cam = tum3();
  ASSERT_GT(cv::countNonZero(room.floor_px), 20000);
  ASSERT_GT(cv::countNonZero(room.wall_px), 100000);
  const RegionGrowParams params;  // step 0.03, band 0.35, extent 0.8
  const cv::Mat grown =
      lrd::dynamic::grow_regions(room.depth, {{320.0f, 300.0f, 1.5f}}, cam.fx, cam.fy, params);
  ASSERT_EQ(grown.type(), CV_8UC1);
  ASSERT_EQ(grown.size(), room.depth.size());
  EXPECT_GE(share(grown, room.box_px), 0.95);
  EXPECT_LT(share(grown, room.wall_px), 0.01);
  // It runs onto the floor the box stands on, but only within the depth band of the seed.
  int floor_grown = 0;
  for (int v = 0; v < grown.rows; ++v)
    for (int u = 0; u < grown.cols; ++u) {
      if (!grown.at<std::uint8_t>(v, u) || !room.floor_px.at<std::uint8_t>(v, u)) continue;
      ++floor_grown;
      EXPECT_LE(std::abs(room.sampled(u, v) - 1.5), params.band + 1e-6) << u << "," << v;
    }
  EXPECT_GT(floor_grown, 0);
  // ... and within the lateral extent: 0.8 m at 1.5 m is 286 px, the floor is 640 px wide.
  const cv::Rect r = cv::boundingRect(grown);
  EXPECT_LE(320 - r.x, params.extent * cam.fx / (1.5 - params.band) + 2);
  EXPECT_GT(r.x, 0);
  EXPECT_LT(r.x + r.width, 640);
}

TEST(DepthRegionGrower, LateralExtentBoundsARegionOnAWideWall) {
  const auto& cam = tum3();
  const cv::Mat wall(480, 640, CV_32F, cv::Scalar(3.0f));
  RegionGrowParams params;
  const cv::Mat grown = lrd::dynamic::grow_regions(wall, {{320.0f, 240.0f, 3.0f}}, cam.fx, cam.fy, params);
  const cv::Rect r = cv::boundingRect(grown);
  // Sideways within 0.8 m (142.8 px at 3 m), vertically within 1.5 x 0.8 m (215.7 px).
  const double half_w = params.extent * cam.fx / 3.0, half_h = 1.5 * params.extent * cam.fy / 3.0;
  EXPECT_NEAR(320 - r.x, half_w, 3.0);
  EXPECT_NEAR(r.x + r.width - 320, half_w, 3.0);
  EXPECT_NEAR(240 - r.y, half_h, 3.0);
  EXPECT_NEAR(r.y + r.height - 240, half_h, 3.0);
  EXPECT_EQ(cv::countNonZero(grown(r)), r.area());  // a solid rectangle

  params.extent = 0.4;
  const cv::Rect r2 =
      cv::boundingRect(lrd::dynamic::grow_regions(wall, {{320.0f, 240.0f, 3.0f}}, cam.fx, cam.fy, params));
  EXPECT_NEAR(r2.width, 2 * 0.4 * cam.fx / 3.0, 6.0);
}

TEST(DepthRegionGrower, DepthBandBoundsARegionOnASlantedPlane) {
  const auto& cam = tum3();
  cv::Mat slant(480, 640, CV_32F);
  for (int v = 0; v < slant.rows; ++v)
    for (int u = 0; u < slant.cols; ++u) slant.at<float>(v, u) = static_cast<float>(1.0 + 0.002 * u);
  for (const double band : {0.35, 0.11}) {  // band edges between pixels
    SCOPED_TRACE(band);
    RegionGrowParams params;
    params.band = band;
    const cv::Mat grown =
        lrd::dynamic::grow_regions(slant, {{320.0f, 240.0f, 1.64f}}, cam.fx, cam.fy, params);
    const double d0 = slant.at<float>(240, 320);
    // Along the seed's row every column within the band is grown and none outside it.
    for (int u = 0; u < 640; ++u) {
      const double d = slant.at<float>(240, 2 * (u / 2));
      EXPECT_EQ(grown.at<std::uint8_t>(240, u) != 0, std::abs(d - d0) <= band + 1e-6) << "column " << u;
    }
    const cv::Rect r = cv::boundingRect(grown);
    EXPECT_NEAR(r.width, 2 * band / 0.002, 5.0);
  }
}

TEST(DepthRegionGrower, SeedsInHolesAndSeveralObjects) {
  const auto& cam = tum3();
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(3.0f));
  const cv::Rect a(100, 100, 80, 120), b(400, 200, 100, 100);
  depth(a).setTo(1.2f);
  depth(b).setTo(2.0f);
  depth(cv::Rect(140, 160, 2, 2)).setTo(0.0f);    // no depth at the seed (one half-resolution pixel)
  depth(cv::Rect(110, 110, 20, 20)).setTo(0.0f);  // a hole elsewhere in box a
  const RegionGrowParams params;
  // One seed without depth under it (its own depth given), one on box b.
  const cv::Mat grown = lrd::dynamic::grow_regions(depth, {{140.0f, 160.0f, 1.2f}, {450.0f, 250.0f, 2.0f}},
                                                   cam.fx, cam.fy, params);
  EXPECT_EQ(cv::countNonZero(grown(b)), b.area());
  EXPECT_EQ(cv::countNonZero(grown(a)), a.area() - 20 * 20);  // all but the hole, around it
  EXPECT_LE(cv::countNonZero(grown), a.area() + b.area() + 4);
  // A seed in a hole without a depth of its own grows nothing; no seeds, nothing.
  EXPECT_EQ(
      cv::countNonZero(lrd::dynamic::grow_regions(depth, {{140.0f, 160.0f, 0.0f}}, cam.fx, cam.fy, params)),
      0);
  EXPECT_EQ(cv::countNonZero(lrd::dynamic::grow_regions(depth, {}, cam.fx, cam.fy, params)), 0);
  // Seeds outside the image are clamped to its border.
  const cv::Mat edge = lrd::dynamic::grow_regions(depth, {{-50.0f, 1000.0f, 3.0f}}, cam.fx, cam.fy, params);
  EXPECT_EQ(edge.at<std::uint8_t>(479, 0), 255);
}
