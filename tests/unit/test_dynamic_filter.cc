// Dynamic scenes without a network: the multi-view geometry check on a textured plane in front of
// which a textured box appears (the `dynamic` config section: test_dynamic_params.cc; mask
// propagation and region growing: test_mask_regions.cc).
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "lrd/dynamic/depth_region_grower.h"
#include "lrd/dynamic/dynamic_point_filter.h"
#include "lrd/dynamic/mask_propagator.h"
#include "lrd/map/map.h"
#include "lrd/util/error.h"
#include "textured_plane.h"

using lrd::dynamic::DynamicPointFilter;
using lrd::dynamic::GeometryCheckParams;
using lrd::dynamic::RegionGrowParams;
using lrd::dynamic::RegionSeed;

namespace {

const lrd::camera::PinholeCamera& tum3() {
  static const lrd::camera::PinholeCamera cam = lrd::camera::camera_preset("tum3");
  return cam;
}

}  // namespace

// --- the multi-view geometry check

namespace {

// Share of the nonzero pixels of `part` that `grown` covers.
double share(const cv::Mat& grown, const cv::Mat& part) {
  return static_cast<double>(cv::countNonZero(grown & part)) / cv::countNonZero(part);
}

}  // namespace

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
      if (k % 2)
        cv::rectangle(box_texture_, cv::Rect(c.x, c.y, size, rng.uniform(3, 16)), grey, cv::FILLED);
      else
        cv::circle(box_texture_, c, size / 2 + 1, grey, cv::FILLED, cv::LINE_AA);
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

  lrd::data::Frame frame(std::uint64_t id, double timestamp, const View& view,
                         const Eigen::Isometry3d& T_cw) {
    lrd::data::Frame f(id, timestamp, view.grey, view.depth, cv::Mat(), extractor_, undistorter_,
                       plane_.camera());
    f.set_pose(T_cw);
    return f;
  }

  // A keyframe of the view from T_cw at `timestamp` (features and depths; no map points needed).
  lrd::map::KeyFrame* keyframe(lrd::map::Map& map, std::uint64_t id, double timestamp,
                               const Eigen::Isometry3d& T_cw, bool with_box = false) {
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
  const double box_share =
      static_cast<double>(cv::countNonZero(view.box)) / static_cast<double>(view.box.total());
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

// In `full` mode the segmentation has masked the people before the check: seeds on a masked
// object are not grown (grown, they leaked into what the object touches: a seated person into the
// chair and desk); an object the mask missed in part is still found whole from its unmasked seeds.
TEST(DynamicPointFilter, ObjectsTheSegmentationMaskedAreNotGrownAgain) {
  BoxScene scene;
  lrd::map::Map map;
  const std::vector<lrd::map::KeyFrame*> kfs{scene.keyframe(map, 0, 0.0, kf0_pose()),
                                             scene.keyframe(map, 1, 0.5, kf1_pose())};
  const BoxScene::View view = scene.render(current_pose(), true);
  const DynamicPointFilter filter{GeometryCheckParams{}};

  lrd::data::Frame masked = scene.frame(10, 1.0, view, current_pose());
  cv::dilate(view.box, masked.dynamic_mask, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
  const auto whole = filter.check(masked, view.depth, kfs);
  EXPECT_GT(whole.judged, 500);
  EXPECT_LT(whole.seeds, GeometryCheckParams{}.min_seeds);
  EXPECT_TRUE(whole.mask.empty());
  EXPECT_EQ(whole.flagged_keypoints, 0);

  // The mask holds the box's left half only.
  lrd::data::Frame half = scene.frame(11, 1.0, view, current_pose());
  cv::Rect box_rect = cv::boundingRect(view.box);
  box_rect.width /= 2;
  half.dynamic_mask = cv::Mat::zeros(view.box.size(), CV_8U);
  view.box(box_rect).copyTo(half.dynamic_mask(box_rect));
  const auto part = filter.check(half, view.depth, kfs);
  EXPECT_GT(part.seeds, 20);
  ASSERT_FALSE(part.mask.empty());
  EXPECT_GE(share(part.mask, view.box), 0.95);
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
    const lrd::dynamic::GeometryCheckResult r =
        DynamicPointFilter{GeometryCheckParams{}}.check(frame, view.depth, kfs);
    EXPECT_EQ(r.keyframes, 2);
    EXPECT_GT(r.judged, 500);
    EXPECT_LT(r.seeds, 3);
    EXPECT_EQ(r.flagged_keypoints, 0);
    EXPECT_TRUE(r.mask.empty());
    EXPECT_EQ(std::count(r.dynamic.begin(), r.dynamic.end(), true), 0);
  }
}

// Seen from keyframes 20-25 cm to the side, a wide band of the plane behind the (static) box is
// hidden by it now: dense enough to pass the seed support. The map's own points on the box at the
// depth now measured say it is static foreground hiding the plane, not a moving object.
TEST(DynamicPointFilter, StaticForegroundHidingMappedPointsIsNotMotion) {
  BoxScene scene;
  lrd::map::Map map;
  const Eigen::Isometry3d left = lrd::test::pose(0.0, 0.0, 0.0, 0.22, 0.0, 0.0);
  const Eigen::Isometry3d right = lrd::test::pose(0.0, 0.0, 0.0, -0.2, 0.03, 0.0);
  const std::vector<lrd::map::KeyFrame*> kfs{scene.keyframe(map, 0, 0.0, left, true),
                                             scene.keyframe(map, 1, 0.5, right, true)};
  const BoxScene::View view = scene.render(current_pose(), true);
  const lrd::data::Frame frame = scene.frame(5, 1.0, view, current_pose());
  GeometryCheckParams without;
  without.known_surface_px = 0;
  const auto occluded = DynamicPointFilter{without}.check(frame, view.depth, kfs);
  EXPECT_GT(occluded.judged, 500);
  EXPECT_GT(occluded.flagged_keypoints, 20);  // the static box, found "moving"
  const auto r = DynamicPointFilter{GeometryCheckParams{}}.check(frame, view.depth, kfs);
  EXPECT_EQ(r.judged, occluded.judged);
  EXPECT_LT(r.seeds, 3);
  EXPECT_EQ(r.flagged_keypoints, 0);
  EXPECT_TRUE(r.mask.empty());

  // An object that appeared is still found: the map has no points at its depth there.
  const std::vector<lrd::map::KeyFrame*> empty_room{scene.keyframe(map, 2, 0.0, left, false),
                                                    scene.keyframe(map, 3, 0.5, right, false)};
  const auto appeared = DynamicPointFilter{GeometryCheckParams{}}.check(frame, view.depth, empty_room);
  EXPECT_GT(appeared.seeds, 50);
  ASSERT_FALSE(appeared.mask.empty());
  EXPECT_GE(share(appeared.mask, view.box), 0.95);
}

// The pose rests on the frame's inlier map matches; a check flagging most of them is not to be
// applied, one flagging keypoints without matches (a new object) or few matched ones is.
TEST(DynamicPointFilter, ACheckFlaggingMostOfThePosesMatchesIsRecognised) {
  BoxScene scene;
  lrd::map::Map map;
  lrd::map::KeyFrame* kf = scene.keyframe(map, 0, 0.0, kf0_pose());
  const BoxScene::View view = scene.render(current_pose(), false);
  lrd::data::Frame frame = scene.frame(5, 1.0, view, current_pose());
  ASSERT_GT(frame.size(), 200u);
  lrd::map::MapPoint* point = map.create_map_point(Eigen::Vector3d(0.0, 0.0, 2.2), kf, 0);
  // 100 matched keypoints, 5 of them outliers.
  for (std::size_t i = 0; i < 100; ++i) frame.map_points[i] = point;
  for (std::size_t i = 0; i < 5; ++i) frame.outliers[i] = true;
  const auto flag = [&](std::size_t from, std::size_t to) {
    std::vector<bool> dynamic(frame.size(), false);
    for (std::size_t i = from; i < to; ++i) dynamic[i] = true;
    return dynamic;
  };
  using lrd::dynamic::flags_most_pose_matches;
  EXPECT_FALSE(flags_most_pose_matches(frame, flag(0, 0)));
  EXPECT_FALSE(flags_most_pose_matches(frame, flag(100, frame.size())));  // none of the matches
  EXPECT_FALSE(flags_most_pose_matches(frame, flag(0, 52)));              // 47 of 95 inliers: not most
  EXPECT_TRUE(flags_most_pose_matches(frame, flag(0, 53)));               // 48 of 95
  EXPECT_TRUE(flags_most_pose_matches(frame, flag(0, frame.size())));
  // Too few matches to judge by.
  for (std::size_t i = 30; i < 100; ++i) frame.map_points[i] = nullptr;
  EXPECT_FALSE(flags_most_pose_matches(frame, flag(0, frame.size())));
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
  lrd::data::Frame f(static_cast<std::uint64_t>(timestamp * 1000), timestamp, grey, depth, cv::Mat(),
                     extractor, undistorter, tum3());
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
  lrd::map::KeyFrame* side = blank_keyframe(map, 0.2, camera_at(V(0, 0.3, 0)));  // 0.3
  lrd::map::KeyFrame* turned =
      blank_keyframe(map, 0.3, camera_at(V(0, 0, 0), 0.5236));                       // 0.5 x 30 deg = 0.26
  lrd::map::KeyFrame* recent = blank_keyframe(map, 0.95, camera_at(V(0.01, 0, 0)));  // too young
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
  EXPECT_EQ(DynamicPointFilter(params).select_keyframes(camera_at(V(0, 0, 0), 0.5236), 1.0, all).front(),
            turned);
  params.min_keyframe_age_s = 0.75;  // `turned` (0.3 s) is now too young
  EXPECT_EQ(DynamicPointFilter(params).select_keyframes(here, 1.0, all), (List{origin, side, far}));
  params.min_keyframe_age_s = 0.85;
  EXPECT_EQ(DynamicPointFilter(params).select_keyframes(here, 1.0, all), (List{origin, far}));
  EXPECT_TRUE(filter.select_keyframes(here, 1.0, {}).empty());
}
