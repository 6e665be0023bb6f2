// Dynamic scenes without a network: the `dynamic` config section, carrying an older mask to the
// current frame (mask propagation), depth region growing, and the multi-view geometry check on
// a textured plane in front of which a textured box appears.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "lrd/config/config.h"
#include "lrd/dynamic/depth_region_grower.h"
#include "lrd/dynamic/dynamic_params.h"
#include "lrd/dynamic/dynamic_point_filter.h"
#include "lrd/dynamic/mask_propagator.h"
#include "lrd/util/error.h"
#include "temp_dir.h"
#include "textured_plane.h"
#include "error_of.h"

namespace fs = std::filesystem;
using lrd::dynamic::DynamicMode;
using lrd::dynamic::DynamicParams;
using lrd::dynamic::DynamicPointFilter;
using lrd::dynamic::GeometryCheckParams;
using lrd::dynamic::RegionGrowParams;
using lrd::dynamic::RegionSeed;

namespace {

using lrd::test::error_of;

const lrd::camera::PinholeCamera& tum3() {
  static const lrd::camera::PinholeCamera cam = lrd::camera::camera_preset("tum3");
  return cam;
}

cv::Point2d centroid(const cv::Mat& mask) {
  const cv::Moments m = cv::moments(mask, true);
  return {m.m10 / m.m00, m.m01 / m.m00};
}

}  // namespace

// --- the `dynamic` config section

TEST(DynamicParams, ModesParseAndPrint) {
  for (DynamicMode m : {DynamicMode::Static, DynamicMode::Semantic, DynamicMode::Geometric, DynamicMode::Full})
    EXPECT_EQ(lrd::dynamic::parse_mode(lrd::dynamic::to_string(m)), m);
  EXPECT_EQ(lrd::dynamic::to_string(DynamicMode::Full), "full");
  EXPECT_EQ(lrd::dynamic::parse_mode("geometric"), DynamicMode::Geometric);
  for (const std::string bad : {"Full", "", "semantics", "dynamic"}) {
    const std::string msg = error_of([&] { (void)lrd::dynamic::parse_mode(bad); });
    EXPECT_NE(msg.find("'" + bad + "'"), std::string::npos) << msg;
    for (const char* choice : {"static", "semantic", "geometric", "full"})
      EXPECT_NE(msg.find(choice), std::string::npos) << msg;
  }
  EXPECT_FALSE(lrd::dynamic::uses_segmentation(DynamicMode::Static));
  EXPECT_FALSE(lrd::dynamic::uses_geometry(DynamicMode::Static));
  EXPECT_TRUE(lrd::dynamic::uses_segmentation(DynamicMode::Semantic));
  EXPECT_FALSE(lrd::dynamic::uses_geometry(DynamicMode::Semantic));
  EXPECT_FALSE(lrd::dynamic::uses_segmentation(DynamicMode::Geometric));
  EXPECT_TRUE(lrd::dynamic::uses_geometry(DynamicMode::Geometric));
  EXPECT_TRUE(lrd::dynamic::uses_segmentation(DynamicMode::Full));
  EXPECT_TRUE(lrd::dynamic::uses_geometry(DynamicMode::Full));
}

TEST(DynamicParams, FromConfig) {
  // Defaults from an empty section.
  const DynamicParams d = DynamicParams::from_config(lrd::config::NodeReader());
  EXPECT_EQ(d.mode, DynamicMode::Geometric);  // needs no model
  EXPECT_EQ(d.geometry.keyframes, 5);
  EXPECT_DOUBLE_EQ(d.geometry.max_parallax_deg, 30.0);
  EXPECT_DOUBLE_EQ(d.geometry.depth_threshold, 0.10);
  EXPECT_DOUBLE_EQ(d.geometry.depth_threshold_slope, 0.02);
  EXPECT_DOUBLE_EQ(d.geometry.max_depth, 6.0);
  EXPECT_EQ(d.geometry.neighbourhood, 2);
  EXPECT_DOUBLE_EQ(d.geometry.neighbourhood_agreement, 0.7);
  EXPECT_EQ(d.geometry.min_seeds, 3);
  EXPECT_DOUBLE_EQ(d.geometry.grow_band, 0.35);
  EXPECT_DOUBLE_EQ(d.geometry.min_keyframe_age_s, 0.2);

  lrd::test::TempDir tmp("dynamic_config");
  auto read = [&](const std::string& text) {
    const fs::path file = tmp.write("config.yaml", text);
    return DynamicParams::from_config(lrd::config::load_config(file).dynamic);
  };
  const DynamicParams p = read(
      "dynamic:\n  mode: full\n  geometry:\n    keyframes: 3\n    max_parallax_deg: 20\n"
      "    depth_threshold: 0.2\n    neighbourhood: 1\n    min_seeds: 5\n    grow_extent: 0.5\n"
      "    min_keyframe_age_s: 0.5\n");
  EXPECT_EQ(p.mode, DynamicMode::Full);
  EXPECT_EQ(p.geometry.keyframes, 3);
  EXPECT_DOUBLE_EQ(p.geometry.max_parallax_deg, 20.0);
  EXPECT_DOUBLE_EQ(p.geometry.depth_threshold, 0.2);
  EXPECT_EQ(p.geometry.neighbourhood, 1);
  EXPECT_EQ(p.geometry.min_seeds, 5);
  EXPECT_DOUBLE_EQ(p.geometry.grow_extent, 0.5);
  EXPECT_DOUBLE_EQ(p.geometry.min_keyframe_age_s, 0.5);
  EXPECT_DOUBLE_EQ(p.geometry.grow_step, 0.03);  // untouched: default

  std::string msg = error_of([&] { (void)read("dynamic:\n  mode: fulll\n"); });
  EXPECT_NE(msg.find("dynamic.mode"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fulll"), std::string::npos) << msg;
  EXPECT_NE(msg.find("config.yaml:2"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  geometry:\n    keyframe: 3\n"); });
  EXPECT_NE(msg.find("dynamic.geometry.keyframe"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  mod: full\n"); });
  EXPECT_NE(msg.find("dynamic.mod"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  geometry:\n    keyframes: 0\n"); });
  EXPECT_NE(msg.find("dynamic.geometry.keyframes"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  geometry:\n    neighbourhood_agreement: 1.5\n"); });
  EXPECT_NE(msg.find("dynamic.geometry.neighbourhood_agreement"), std::string::npos) << msg;
  msg = error_of([&] { (void)read("dynamic:\n  geometry:\n    depth_threshold: 0\n"); });
  EXPECT_NE(msg.find("dynamic.geometry.depth_threshold"), std::string::npos) << msg;
}

// --- mask propagation

TEST(MaskPropagator, IdentityMovesNothing) {
  cv::Mat mask = cv::Mat::zeros(480, 640, CV_8UC1), depth(480, 640, CV_32F, cv::Scalar(2.0f));
  mask(cv::Rect(300, 200, 40, 30)).setTo(255);
  mask(cv::Rect(100, 350, 7, 9)).setTo(1);  // any nonzero value is dynamic
  const cv::Mat out = lrd::dynamic::propagate_mask(mask, depth, Eigen::Isometry3d::Identity(), tum3());
  ASSERT_EQ(out.type(), CV_8UC1);
  ASSERT_EQ(out.size(), mask.size());
  EXPECT_EQ(cv::countNonZero(mask & ~out), 0);                            // every pixel stays set
  EXPECT_EQ(cv::countNonZero((out != 0) & (out != 255)), 0);              // 255 = dynamic
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
      cv::Mat mask = cv::Mat::zeros(480, 640, CV_8UC1), depth(480, 640, CV_32F, cv::Scalar(static_cast<float>(z)));
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
  EXPECT_EQ(cv::countNonZero(out(with_depth)), 0);               // moved away
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

// Radii from 12 up (masks grown with age) are dilated at half resolution: the disc is covered,
// and the edge may overshoot by a few pixels (2x2 blocks, rounding).
TEST(MaskPropagator, LargeDilationCoversTheDiscWithinAFewPixels) {
  for (const int radius : {12, 20, 31}) {
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
  const cv::Mat grown = lrd::dynamic::grow_regions(room.depth, {{320.0f, 300.0f, 1.5f}}, cam.fx, cam.fy, params);
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
    const cv::Mat grown = lrd::dynamic::grow_regions(slant, {{320.0f, 240.0f, 1.64f}}, cam.fx, cam.fy, params);
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
  const cv::Mat grown =
      lrd::dynamic::grow_regions(depth, {{140.0f, 160.0f, 1.2f}, {450.0f, 250.0f, 2.0f}}, cam.fx, cam.fy, params);
  EXPECT_EQ(cv::countNonZero(grown(b)), b.area());
  EXPECT_EQ(cv::countNonZero(grown(a)), a.area() - 20 * 20);  // all but the hole, around it
  EXPECT_LE(cv::countNonZero(grown), a.area() + b.area() + 4);
  // A seed in a hole without a depth of its own grows nothing; no seeds, nothing.
  EXPECT_EQ(cv::countNonZero(lrd::dynamic::grow_regions(depth, {{140.0f, 160.0f, 0.0f}}, cam.fx, cam.fy, params)), 0);
  EXPECT_EQ(cv::countNonZero(lrd::dynamic::grow_regions(depth, {}, cam.fx, cam.fy, params)), 0);
  // Seeds outside the image are clamped to its border.
  const cv::Mat edge = lrd::dynamic::grow_regions(depth, {{-50.0f, 1000.0f, 3.0f}}, cam.fx, cam.fy, params);
  EXPECT_EQ(edge.at<std::uint8_t>(479, 0), 255);
}

// --- the multi-view geometry check

namespace {

// The textured plane of textured_plane.h (about 2.2 m away) and, when `with_box`, a textured
// box face at world z = 1.3 m in front of it.
class BoxScene {
 public:
  static constexpr double kBoxZ = 1.3, kX0 = -0.30, kX1 = 0.20, kY0 = -0.25, kY1 = 0.20;
  static constexpr double kTexelsPerMetre = 400.0;

  BoxScene() : undistorter_(plane_.camera()) {
    cv::RNG rng(11);
    box_texture_.create(256, 256, CV_8U);
    rng.fill(box_texture_, cv::RNG::UNIFORM, 40, 216);
    cv::GaussianBlur(box_texture_, box_texture_, cv::Size(0, 0), 2.0);
    for (int k = 0; k < 260; ++k) {
      const cv::Point c(rng.uniform(0, 256), rng.uniform(0, 256));
      const int size = rng.uniform(3, 16);
      const cv::Scalar grey(rng.uniform(0, 256));
      if (k % 2) cv::rectangle(box_texture_, cv::Rect(c.x, c.y, size, rng.uniform(3, 16)), grey, cv::FILLED);
      else cv::circle(box_texture_, c, size / 2 + 1, grey, cv::FILLED, cv::LINE_AA);
    }
    cv::GaussianBlur(box_texture_, box_texture_, cv::Size(0, 0), 0.7);
  }

  struct View {
    cv::Mat grey, depth, box;  // box: CV_8U, 255 where the box is seen
  };

  [[nodiscard]] View render(const Eigen::Isometry3d& T_cw, bool with_box) const {
    const auto img = plane_.render(T_cw);
    View view{img.grey, img.depth, cv::Mat::zeros(img.grey.size(), CV_8U)};
    if (!with_box) return view;
    const auto& cam = plane_.camera();
    const Eigen::Isometry3d T_wc = T_cw.inverse();
    const Eigen::Vector3d C = T_wc.translation();
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) {
        const Eigen::Vector3d ray =
            T_wc.linear() * Eigen::Vector3d((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
        const double lambda = (kBoxZ - C.z()) / ray.z();  // = camera depth (the ray has z = 1)
        if (lambda <= 0.0) continue;
        const Eigen::Vector3d X = C + lambda * ray;
        if (X.x() < kX0 || X.x() >= kX1 || X.y() < kY0 || X.y() >= kY1) continue;
        const int tx = std::clamp(static_cast<int>((X.x() - kX0) * kTexelsPerMetre), 0, 255);
        const int ty = std::clamp(static_cast<int>((X.y() - kY0) * kTexelsPerMetre), 0, 255);
        view.grey.at<std::uint8_t>(v, u) = box_texture_.at<std::uint8_t>(ty, tx);
        view.depth.at<float>(v, u) = static_cast<float>(lambda);
        view.box.at<std::uint8_t>(v, u) = 255;
      }
    return view;
  }

  lrd::data::Frame frame(std::uint64_t id, double timestamp, const View& view, const Eigen::Isometry3d& T_cw) {
    lrd::data::Frame f(id, timestamp, view.grey, view.depth, cv::Mat(), extractor_, undistorter_, plane_.camera());
    f.set_pose(T_cw);
    return f;
  }

  // A keyframe of the view from T_cw at `timestamp` (features and depths; no map points needed).
  lrd::map::KeyFrame* keyframe(lrd::map::Map& map, std::uint64_t id, double timestamp, const Eigen::Isometry3d& T_cw,
                               bool with_box = false) {
    return map.create_keyframe(frame(id, timestamp, render(T_cw, with_box), T_cw));
  }

 private:
  lrd::test::TexturedPlane plane_{7};
  lrd::features::OrbExtractor extractor_{lrd::features::OrbParams{}};
  lrd::features::KeypointUndistorter undistorter_;
  cv::Mat box_texture_;
};

const Eigen::Isometry3d& kf0_pose() {
  static const Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  return T;
}
const Eigen::Isometry3d& kf1_pose() {
  static const Eigen::Isometry3d T = lrd::test::pose(0.0, 0.03, 0.0, 0.06, 0.0, 0.0);
  return T;
}
const Eigen::Isometry3d& current_pose() {
  static const Eigen::Isometry3d T = lrd::test::pose(0.01, -0.02, 0.0, -0.04, 0.02, 0.03);
  return T;
}

// Keypoint i's pixel is within `margin` pixels of the box's outline.
bool near_outline(const cv::Mat& box, const cv::KeyPoint& kp, int margin) {
  const int u = static_cast<int>(std::lround(kp.pt.x)), v = static_cast<int>(std::lround(kp.pt.y));
  const std::uint8_t centre = box.at<std::uint8_t>(v, u);
  for (int dv = -margin; dv <= margin; ++dv)
    for (int du = -margin; du <= margin; ++du) {
      const int x = std::clamp(u + du, 0, box.cols - 1), y = std::clamp(v + dv, 0, box.rows - 1);
      if (box.at<std::uint8_t>(y, x) != centre) return true;
    }
  return false;
}

}  // namespace

TEST(DynamicPointFilter, FlagsTheKeypointsOfAnObjectThatAppeared) {
  BoxScene scene;
  lrd::map::Map map;
  const std::vector<lrd::map::KeyFrame*> kfs{scene.keyframe(map, 0, 0.0, kf0_pose()),
                                             scene.keyframe(map, 1, 0.5, kf1_pose())};
  ASSERT_GT(kfs[0]->size(), 500u);
  const BoxScene::View view = scene.render(current_pose(), true);
  const double box_share = static_cast<double>(cv::countNonZero(view.box)) / static_cast<double>(view.box.total());
  ASSERT_GT(box_share, 0.08);
  ASSERT_LT(box_share, 0.3);
  const lrd::data::Frame frame = scene.frame(10, 1.0, view, current_pose());

  const DynamicPointFilter filter{GeometryCheckParams{}};
  const lrd::dynamic::GeometryCheckResult r = filter.check(frame, view.depth, kfs);
  EXPECT_EQ(r.keyframes, 2);
  EXPECT_GT(r.judged, 500);
  EXPECT_GT(r.seeds, 50);
  EXPECT_EQ(r.parallax_skipped, 0);
  ASSERT_EQ(r.dynamic.size(), frame.size());
  ASSERT_FALSE(r.mask.empty());
  ASSERT_EQ(r.mask.type(), CV_8UC1);
  ASSERT_EQ(r.mask.size(), view.box.size());
  // The grown region is the box (give or take the half-resolution grid and any dilation of the
  // regions, region_dilation_px: nothing farther than 12 px from the box).
  EXPECT_GE(share(r.mask, view.box), 0.95);
  cv::Mat near_box;
  cv::dilate(view.box, near_box, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(25, 25)));
  EXPECT_LT(share(r.mask, ~near_box), 0.005);

  int on_box = 0, on_box_flagged = 0, off_box = 0, off_box_flagged = 0, flagged = 0;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    flagged += r.dynamic[i];
    const cv::KeyPoint& kp = frame.keypoints()[i];
    if (near_outline(view.box, kp, 8)) continue;  // ambiguous: half resolution, dilation
    const bool box = view.box.at<std::uint8_t>(static_cast<int>(std::lround(kp.pt.y)),
                                               static_cast<int>(std::lround(kp.pt.x))) != 0;
    (box ? on_box : off_box) += 1;
    (box ? on_box_flagged : off_box_flagged) += r.dynamic[i] ? 1 : 0;
  }
  EXPECT_EQ(flagged, r.flagged_keypoints);
  ASSERT_GT(on_box, 40);
  ASSERT_GT(off_box, 400);
  EXPECT_GE(on_box_flagged, 0.8 * on_box) << on_box_flagged << " of " << on_box;
  EXPECT_LT(off_box_flagged, 0.05 * off_box) << off_box_flagged << " of " << off_box;
}

// With the box in every view, plane points seen beside the box from a keyframe fall behind it
// from the current pose (plain occlusion at a depth edge, small parallax): they must not make the
// static box dynamic.
TEST(DynamicPointFilter, FlagsNothingInAnUnchangedScene) {
  BoxScene scene;
  lrd::map::Map map;
  for (const bool with_box : {false, true}) {
    SCOPED_TRACE(with_box ? "box in every view" : "no box");
    const std::uint64_t base = with_box ? 10 : 0;
    const std::vector<lrd::map::KeyFrame*> kfs{scene.keyframe(map, base, 0.0, kf0_pose(), with_box),
                                               scene.keyframe(map, base + 1, 0.5, kf1_pose(), with_box)};
    const BoxScene::View view = scene.render(current_pose(), with_box);
    const lrd::data::Frame frame = scene.frame(base + 5, 1.0, view, current_pose());
    const lrd::dynamic::GeometryCheckResult r = DynamicPointFilter{GeometryCheckParams{}}.check(frame, view.depth, kfs);
    EXPECT_EQ(r.keyframes, 2);
    EXPECT_GT(r.judged, 500);
    EXPECT_LT(r.seeds, 3);
    EXPECT_EQ(r.flagged_keypoints, 0);
    EXPECT_TRUE(r.mask.empty());
    EXPECT_EQ(std::count(r.dynamic.begin(), r.dynamic.end(), true), 0);
  }
}

TEST(DynamicPointFilter, AnObjectThatLeftIsNotFlagged) {
  // The box was there in the keyframes and is gone now: its points project in front of the
  // plane seen there now (z_proj < z'), which is not what a moving object in front looks like.
  BoxScene scene;
  lrd::map::Map map;
  const std::vector<lrd::map::KeyFrame*> kfs{scene.keyframe(map, 0, 0.0, kf0_pose(), true),
                                             scene.keyframe(map, 1, 0.5, kf1_pose(), true)};
  const BoxScene::View view = scene.render(current_pose(), false);
  const lrd::data::Frame frame = scene.frame(5, 1.0, view, current_pose());
  const auto r = DynamicPointFilter{GeometryCheckParams{}}.check(frame, view.depth, kfs);
  EXPECT_GT(r.judged, 500);
  EXPECT_EQ(r.flagged_keypoints, 0);
}

TEST(DynamicPointFilter, RecentKeyframesAreNotCompared) {
  BoxScene scene;
  lrd::map::Map map;
  const std::vector<lrd::map::KeyFrame*> kfs{scene.keyframe(map, 0, 0.0, kf0_pose()),
                                             scene.keyframe(map, 1, 0.5, kf1_pose())};
  const BoxScene::View view = scene.render(current_pose(), true);
  // At 0.6 s the keyframe of 0.5 s is too young (min_keyframe_age_s 0.2); the box is still found
  // from the older one.
  const lrd::data::Frame frame = scene.frame(10, 0.6, view, current_pose());
  const auto r = DynamicPointFilter{GeometryCheckParams{}}.check(frame, view.depth, kfs);
  EXPECT_EQ(r.keyframes, 1);
  EXPECT_GT(r.seeds, 20);
  EXPECT_GE(share(r.mask, view.box), 0.9);
  // Nothing old enough: nothing compared, nothing flagged.
  const lrd::data::Frame early = scene.frame(11, 0.1, view, current_pose());
  const auto none = DynamicPointFilter{GeometryCheckParams{}}.check(early, view.depth, kfs);
  EXPECT_EQ(none.keyframes, 0);
  EXPECT_EQ(none.judged, 0);
  EXPECT_EQ(none.flagged_keypoints, 0);
  EXPECT_TRUE(none.mask.empty());
  // Fewer seeds than min_seeds (far more than the box gives): nothing flagged.
  // The same input gives the same result.
  const auto again = DynamicPointFilter{GeometryCheckParams{}}.check(frame, view.depth, kfs);
  EXPECT_EQ(again.seeds, r.seeds);
  EXPECT_EQ(again.flagged_keypoints, r.flagged_keypoints);
  EXPECT_EQ(cv::countNonZero(again.mask != r.mask), 0);
  GeometryCheckParams strict;
  strict.min_seeds = 100000;
  const auto few = DynamicPointFilter{strict}.check(frame, view.depth, kfs);
  EXPECT_EQ(few.keyframes, 1);
  EXPECT_GT(few.judged, 500);
  EXPECT_EQ(few.flagged_keypoints, 0);
  EXPECT_TRUE(few.mask.empty());
}

namespace {

// A keyframe without features (blank image), only a pose and a timestamp.
lrd::map::KeyFrame* blank_keyframe(lrd::map::Map& map, double timestamp, const Eigen::Isometry3d& T_cw) {
  static lrd::features::OrbExtractor extractor{lrd::features::OrbParams{}};
  static const lrd::features::KeypointUndistorter undistorter(tum3());
  const cv::Mat grey = cv::Mat::zeros(480, 640, CV_8U), depth = cv::Mat::zeros(480, 640, CV_32F);
  lrd::data::Frame f(static_cast<std::uint64_t>(timestamp * 1000), timestamp, grey, depth, cv::Mat(), extractor,
                     undistorter, tum3());
  f.set_pose(T_cw);
  return map.create_keyframe(f);
}

// World-to-camera pose of a camera at `centre`, turned by `yaw` radians about the vertical axis.
Eigen::Isometry3d camera_at(const Eigen::Vector3d& centre, double yaw = 0.0) {
  Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
  T_wc.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T_wc.translation() = centre;
  return T_wc.inverse();
}

}  // namespace

TEST(DynamicPointFilter, SelectsTheNearestOldEnoughKeyframes) {
  lrd::map::Map map;
  using V = Eigen::Vector3d;
  lrd::map::KeyFrame* origin = blank_keyframe(map, 0.0, camera_at(V(0, 0, 0)));
  lrd::map::KeyFrame* far = blank_keyframe(map, 0.1, camera_at(V(1.0, 0, 0)));
  lrd::map::KeyFrame* side = blank_keyframe(map, 0.2, camera_at(V(0, 0.3, 0)));          // 0.3
  lrd::map::KeyFrame* turned = blank_keyframe(map, 0.3, camera_at(V(0, 0, 0), 0.5236));  // 0.5 x 30 deg = 0.26
  lrd::map::KeyFrame* recent = blank_keyframe(map, 0.95, camera_at(V(0.01, 0, 0)));      // too young
  lrd::map::KeyFrame* bad = blank_keyframe(map, 0.4, camera_at(V(0.02, 0, 0)));
  lrd::map::KeyFrame* twin = blank_keyframe(map, 0.5, camera_at(V(0, -0.3, 0)));  // ties with `side`
  bad->set_bad();
  ASSERT_TRUE(bad->is_bad());
  const std::vector<lrd::map::KeyFrame*> all{far, recent, nullptr, twin, turned, bad, side, origin};

  GeometryCheckParams params;
  params.keyframes = 10;
  const DynamicPointFilter filter(params);
  const Eigen::Isometry3d here = camera_at(V(0, 0, 0));
  using List = std::vector<lrd::map::KeyFrame*>;
  EXPECT_EQ(filter.select_keyframes(here, 1.0, all), (List{origin, turned, side, twin, far}));
  params.keyframes = 3;
  EXPECT_EQ(DynamicPointFilter(params).select_keyframes(here, 1.0, all), (List{origin, turned, side}));
  // Later, the recent one is old enough and second nearest.
  EXPECT_EQ(DynamicPointFilter(params).select_keyframes(here, 1.2, all), (List{origin, recent, turned}));
  // Elsewhere: from (1, 0, 0) `far` is nearest.
  EXPECT_EQ(DynamicPointFilter(params).select_keyframes(camera_at(V(0.9, 0, 0)), 1.0, all).front(), far);
  // A camera looking the other way ranks by angle too: `turned` first at the origin.
  EXPECT_EQ(DynamicPointFilter(params).select_keyframes(camera_at(V(0, 0, 0), 0.5236), 1.0, all).front(), turned);
  params.min_keyframe_age_s = 0.75;  // `turned` (0.3 s) is now too young
  EXPECT_EQ(DynamicPointFilter(params).select_keyframes(here, 1.0, all), (List{origin, side, far}));
  params.min_keyframe_age_s = 0.85;
  EXPECT_EQ(DynamicPointFilter(params).select_keyframes(here, 1.0, all), (List{origin, far}));
  EXPECT_TRUE(filter.select_keyframes(here, 1.0, {}).empty());
}
