// The Bonn-style presets (crowd, person_tracking, moving_box, moving_box_obstructing, balloon,
// synchronous): they render deterministically in both realism profiles with masks of everything
// that moves, and each shows its situation: the followed person in the middle of the image, the
// box labelled only while it moves, the balloon with a label of its own and no network class,
// the jumpers in step.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "lrd/synth/box_mover_actor.h"
#include "lrd/synth/jumping_actor.h"
#include "lrd/synth/presets.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/synth/texture_library.h"

using lrd::synth::MaskLabel;
using lrd::synth::SyntheticSequence;
using lrd::synth::SynthFrame;
using lrd::synth::SynthOptions;

namespace {

const std::vector<std::string> kBonnPresets = {
    "crowd", "person_tracking", "moving_box", "moving_box_obstructing", "balloon", "synchronous"};

SynthOptions bonn_options(const std::string& preset, int frames, const std::string& realism = "clean") {
  SynthOptions o;
  o.preset = preset;
  o.frames = frames;
  o.realism = lrd::synth::realism_profile(realism);
  return o;
}

double label_share(const cv::Mat& mask, int label) {
  return cv::countNonZero(mask == label) / static_cast<double>(mask.total());
}

}  // namespace

TEST(BonnPresets, RenderDeterministicallyInBothProfilesWithMasksOfWhatMoves) {
  const auto textures = SyntheticSequence::load_textures();
  for (const std::string& name : kBonnPresets) {
    for (const std::string realism : {"clean", "tum"}) {
      SCOPED_TRACE(name + " " + realism);
      const SyntheticSequence a(bonn_options(name, 200, realism), textures),
          b(bonn_options(name, 200, realism), textures);
      EXPECT_TRUE(a.spec().held_out);  // outside the segmentation network's training draw
      const SynthFrame fa = a.render(150), fb = b.render(150);
      EXPECT_EQ(cv::norm(fa.rgb, fb.rgb, cv::NORM_INF), 0.0);
      EXPECT_EQ(cv::norm(fa.depth, fb.depth, cv::NORM_INF), 0.0);
      EXPECT_EQ(cv::norm(fa.mask, fb.mask, cv::NORM_INF), 0.0);
      EXPECT_TRUE(fa.pose.isApprox(fb.pose, 0.0));
      // Something moves in view, and every mask value is one of the labels.
      EXPECT_GT(cv::countNonZero(fa.mask), 0);
      double max_label = 0.0;
      cv::minMaxLoc(fa.mask, nullptr, &max_label);
      EXPECT_LE(max_label, static_cast<double>(MaskLabel::kBalloon));
    }
  }
}

TEST(BonnPresets, HandHeldSpeedsComeFromTheTumSequenceTheyAreModelledOn) {
  using lrd::synth::find_preset;
  EXPECT_EQ(lrd::synth::motion_model(find_preset("crowd")), "walking_xyz");
  EXPECT_EQ(lrd::synth::motion_model(find_preset("synchronous")), "walking_static");
  EXPECT_EQ(lrd::synth::motion_model(find_preset("walking_rpy")), "walking_rpy");
  // The following camera moves as the person it follows walks: no TUM sequence sets its speed.
  EXPECT_EQ(lrd::synth::motion_model(find_preset("person_tracking")), "");
  EXPECT_FALSE(lrd::synth::motion_target(find_preset("person_tracking")).has_value());
  EXPECT_DOUBLE_EQ(lrd::synth::motion_target(find_preset("balloon"))->mean_speed,
                   lrd::synth::tum_fr3_motion("walking_xyz")->mean_speed);
}

TEST(BonnPresets, TheFollowedPersonStaysInTheMiddleOfTheImage) {
  const SyntheticSequence seq(bonn_options("person_tracking", 900));
  double travelled = 0.0;
  Eigen::Vector3d last = seq.pose(0).translation();
  for (int i = 0; i < 900; i += 45) {
    SCOPED_TRACE(i);
    const SynthFrame f = seq.render(i, SyntheticSequence::Views::CameraOnly);
    const cv::Mat person = f.mask == static_cast<int>(MaskLabel::kPerson);
    const cv::Moments m = cv::moments(person, true);
    ASSERT_GT(m.m00, 0.05 * 640 * 480);  // 1-2.5 m ahead: a large part of the view
    EXPECT_NEAR(m.m10 / m.m00, 320.0, 80.0);
    EXPECT_NEAR(m.m01 / m.m00, 240.0, 120.0);
    travelled += (f.pose.translation() - last).norm();
    last = f.pose.translation();
  }
  // The camera walks behind them round the room.
  EXPECT_GT(travelled, 10.0);
}

TEST(BonnPresets, TheBoxIsAMovedObjectOnlyWhileItMoves) {
  const auto textures = SyntheticSequence::load_textures();
  lrd::synth::BoxMoveParams p;
  p.home = {3.2f, 0.6f};
  p.spot_a = {3.85f, 1.55f};
  p.spot_b = {3.85f, 3.45f};
  const lrd::synth::BoxMoverActor mover(p, {}, *textures, "person 1");
  int moving = 0, resting = 0;
  for (double t = 0.0; t < mover.period(); t += 0.1) {
    const auto box = mover.box_at(t);
    lrd::synth::TriangleSoup soup;
    mover.add_geometry(t, soup);
    int box_moved = 0, box_static = 0;
    for (const auto& tri : soup.triangles()) {
      if (tri.label == MaskLabel::kMovedObject) ++box_moved;
      if (tri.label == MaskLabel::kStatic) ++box_static;
    }
    if (box.moving) {
      ++moving;
      EXPECT_GT(box_moved, 0);
      EXPECT_EQ(box_static, 0);
    } else {
      ++resting;
      EXPECT_EQ(box_moved, 0);
      EXPECT_GT(box_static, 0);
      // At rest on the floor at one of its two places.
      const Eigen::Vector2f at = box.centre.head<2>();
      EXPECT_LT(std::min((at - p.spot_a).norm(), (at - p.spot_b).norm()), 1e-4f) << t;
      EXPECT_NEAR(box.centre.z(), 0.5f * p.box_size.z(), 1e-5f);
    }
  }
  EXPECT_GT(moving, 20);
  EXPECT_GT(resting, 20);
  // In the preset it is seen moving.
  const SyntheticSequence seq(bonn_options("moving_box", 900), textures);
  double seen_moving = 0.0;
  for (int i = 0; i < 900; i += 30) seen_moving = std::max(seen_moving, label_share(seq.render(i).mask, 2));
  EXPECT_GT(seen_moving, 0.01);
}

TEST(BonnPresets, TheBalloonHasALabelOfItsOwnAndNoNetworkClass) {
  const SyntheticSequence seq(bonn_options("balloon", 600));
  int frames_with_balloon = 0;
  for (int i = 0; i < 600; i += 30) {
    const SynthFrame f = seq.render(i, SyntheticSequence::Views::CameraOnly);
    const cv::Mat balloon = f.mask == static_cast<int>(MaskLabel::kBalloon);
    if (cv::countNonZero(balloon) < 200) continue;
    ++frames_with_balloon;
    // Pascal VOC has no balloon: the network's training data calls it background.
    cv::Mat classes;
    f.voc_class.copyTo(classes, balloon);
    EXPECT_EQ(cv::countNonZero(classes), 0);
  }
  EXPECT_GE(frames_with_balloon, 15);
}

TEST(BonnPresets, TheCrowdCoversMuchOfTheViewAndTheJumpersJumpInStep) {
  const auto textures = SyntheticSequence::load_textures();
  const SyntheticSequence crowd(bonn_options("crowd", 900), textures);
  EXPECT_GE(crowd.actor_descriptions().size(), 4u);
  EXPECT_LE(crowd.actor_descriptions().size(), 6u);
  double mean = 0.0, most = 0.0;
  for (int i = 0; i < 900; i += 30) {
    const double s = label_share(crowd.render(i, SyntheticSequence::Views::CameraOnly).mask, 1);
    mean += s / 30.0;
    most = std::max(most, s);
  }
  EXPECT_GT(mean, 0.2);
  EXPECT_GT(most, 0.5);

  const auto script =
      lrd::synth::build_scene_script(lrd::synth::find_preset("synchronous"), *textures, 1, 30.0);
  std::vector<const lrd::synth::JumpingActor*> jumpers;
  for (const auto& a : script.actors)
    if (const auto* j = dynamic_cast<const lrd::synth::JumpingActor*>(a.get())) jumpers.push_back(j);
  ASSERT_EQ(jumpers.size(), 3u);
  int airborne = 0;
  for (double t = 0.0; t < 20.0; t += 0.05) {
    const bool up = jumpers[0]->lift_at(t) > 0.0f;
    airborne += up;
    for (const auto* j : jumpers) EXPECT_EQ(j->lift_at(t) > 0.0f, up) << t;
  }
  EXPECT_GT(airborne, 40);
}
