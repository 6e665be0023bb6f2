// The realism profile's camera motion (docs/synthetic-benchmark.md): each walking/sitting preset's
// path made as fast as the TUM fr3 sequence it mirrors, by TUM's own 1-s statistics.
#include <gtest/gtest.h>

#include <cstdint>

#include "lrd/eval/motion_statistics.h"
#include "lrd/synth/motion_matching.h"
#include "lrd/synth/presets.h"

using lrd::synth::CameraMotion;
using lrd::synth::HandHeldMotion;

namespace {

lrd::eval::MotionStatistics statistics(const CameraMotion& camera, double duration) {
  lrd::io::Trajectory t;
  for (int i = 0; i * (1.0 / 30.0) < duration; ++i) t.push_back({i / 30.0, camera.pose_at(i / 30.0)});
  return lrd::eval::motion_statistics(t);
}

}  // namespace

TEST(MotionMatching, EveryMirroredPresetMovesAsFastAsItsTumSequence) {
  const char* mirrored[] = {"walking_xyz", "walking_static",     "walking_halfsphere", "walking_rpy",
                            "sitting_xyz", "sitting_halfsphere", "sitting_static"};
  for (const char* name : mirrored) {
    SCOPED_TRACE(name);
    const auto& spec = lrd::synth::find_preset(name);
    const double duration = spec.default_frames / 30.0;
    const auto target = lrd::synth::tum_fr3_motion(name);
    ASSERT_TRUE(target.has_value());
    for (const std::uint64_t seed : {1, 7}) {  // every seed's path is matched on its own
      CameraMotion camera(spec.motion, duration, seed);
      const auto smooth = statistics(camera, duration);
      // The smooth paths are far from TUM's: that is what matching is for.
      EXPECT_GT(std::abs(smooth.mean_angular_speed / target->mean_angular_speed - 1.0), 0.15);
      camera.set_hand_held(lrd::synth::match_motion(camera, *target, duration, 30.0));
      const auto matched = statistics(camera, duration);
      EXPECT_NEAR(matched.mean_speed, target->mean_speed, 0.02 * target->mean_speed);
      EXPECT_NEAR(matched.mean_angular_speed, target->mean_angular_speed, 0.02 * target->mean_angular_speed);
    }
  }
  EXPECT_FALSE(lrd::synth::tum_fr3_motion("walking_loop").has_value());
}

TEST(MotionMatching, TooFastPathsAreScaledDownSlowOnesWander) {
  const auto& xyz = lrd::synth::find_preset("walking_xyz");
  const double d = xyz.default_frames / 30.0;
  const CameraMotion xyz_camera(xyz.motion, d, 1);
  const HandHeldMotion xyz_hand =
      lrd::synth::match_motion(xyz_camera, *lrd::synth::tum_fr3_motion("walking_xyz"), d, 30);
  EXPECT_LT(xyz_hand.path_scale, 0.95);  // ours translates at 0.26 m/s, TUM's at 0.21
  EXPECT_EQ(xyz_hand.translation_sway, 0.0);
  EXPECT_GT(xyz_hand.rotation_sway, 0.0);
  const auto& rpy = lrd::synth::find_preset("walking_rpy");
  const double r = rpy.default_frames / 30.0;
  const CameraMotion rpy_camera(rpy.motion, r, 1);
  const HandHeldMotion rpy_hand =
      lrd::synth::match_motion(rpy_camera, *lrd::synth::tum_fr3_motion("walking_rpy"), r, 30);
  EXPECT_EQ(rpy_hand.path_scale, 1.0);
  EXPECT_GT(rpy_hand.translation_sway, 0.02);  // TUM's rpy camera translates at 0.09 m/s
  EXPECT_LT(rpy_hand.translation_sway, 0.2);
}

TEST(MotionMatching, NoHandHeldMotionIsTheSmoothPathAndSessionsShareIt) {
  const auto& spec = lrd::synth::find_preset("sitting_halfsphere");
  const double d = spec.default_frames / 30.0;
  const CameraMotion smooth(spec.motion, d, 3);
  CameraMotion unchanged = smooth;
  unchanged.set_hand_held(HandHeldMotion{});
  for (double t : {0.0, 3.3, 17.1}) EXPECT_TRUE(smooth.pose_at(t).isApprox(unchanged.pose_at(t), 0.0));
  const HandHeldMotion hand{1.0, 0.05, 0.2};
  CameraMotion one = smooth, two(spec.motion, d, 3, 2);
  one.set_hand_held(hand);
  two.set_hand_held(hand);
  // Map-file session 2 is the hand-held path of session 1 seen from its own standpoint: after the
  // first 4 s the relative transform between them is constant.
  const Eigen::Isometry3d at5 = two.pose_at(5.0) * one.pose_at(5.0).inverse();
  const Eigen::Isometry3d at20 = two.pose_at(20.0) * one.pose_at(20.0).inverse();
  EXPECT_TRUE(at5.isApprox(at20, 1e-9));
  EXPECT_FALSE(one.pose_at(5.0).isApprox(smooth.pose_at(5.0), 1e-3));
}
