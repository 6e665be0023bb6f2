// The constant-velocity motion model (tracking/motion_model.h): velocity per camera frame, frames
// dropped between tracked ones, the measured frame period.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "lrd/tracking/motion_model.h"

namespace lrd::tracking {
namespace {

Eigen::Isometry3d translation(double x) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, 0.0, 0.0);
  return T;
}

TEST(MotionModel, NoVelocityUntilUpdatedAndAfterReset) {
  MotionModel model;
  EXPECT_FALSE(model.has_velocity());
  model.update(translation(0.01), 1.0 / 30.0, translation(0.0), 0.0);
  EXPECT_TRUE(model.has_velocity());
  model.reset();
  EXPECT_FALSE(model.has_velocity());
}

TEST(MotionModel, KeepsTheVelocityOfTheLastStepAndMeasuresTheFramePeriod) {
  MotionModel model;
  EXPECT_DOUBLE_EQ(model.frame_period(30.0), 1.0 / 30.0);  // not measured yet: the camera's rate
  model.update(translation(0.02), 0.04, translation(0.0), 0.0);
  EXPECT_NEAR(model.velocity().translation().x(), 0.02, 1e-12);
  EXPECT_DOUBLE_EQ(model.frame_period(30.0), 0.04);
  const Eigen::Isometry3d next = model.predict(translation(0.02), 0.04, 0.08);
  EXPECT_NEAR(next.translation().x(), 0.04, 1e-12);
}

TEST(MotionModel, PredictsOverDroppedFramesAndDividesTheirMotion) {
  MotionModel model;
  model.update(translation(0.01), 0.1, translation(0.0), 0.0);  // period 0.1 s, 1 cm a frame
  // Two frames dropped: three frame steps since the last tracked frame.
  const Eigen::Isometry3d predicted = model.predict(translation(0.01), 0.1, 0.4);
  EXPECT_NEAR(predicted.translation().x(), 0.04, 1e-9);
  // Tracked there after the gap: the velocity stays one frame's motion, not the gap's.
  model.update(translation(0.04), 0.4, translation(0.01), 0.1);
  EXPECT_NEAR(model.velocity().translation().x(), 0.01, 1e-9);
  EXPECT_DOUBLE_EQ(model.frame_period(30.0), 0.1);  // a gap does not change the period
}

TEST(MotionModel, CapsTheStepsOfALongGap) {
  MotionModel model;
  model.update(translation(0.01), 0.1, translation(0.0), 0.0);
  // 5 s lost: at most ten frame steps are predicted.
  EXPECT_NEAR(model.predict(translation(0.0), 0.0, 5.0).translation().x(), 0.10, 1e-9);
}

}  // namespace
}  // namespace lrd::tracking
