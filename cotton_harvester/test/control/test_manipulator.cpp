#include <gtest/gtest.h>

#include <cmath>

#include "cotton_harvester/control/manipulator_calibration.h"
#include "cotton_harvester/control/stepper_axis_model.h"

using namespace cotton_harvester::control;

// eq. 7: steps = -410.7 d + 483.29, values worked out by hand.
TEST(ManipulatorCalibration, EquationSevenByValue) {
  const ManipulatorCalibration c;
  EXPECT_NEAR(c.verticalStepsFromDistance(0.5), 277.94, 1e-9);
  EXPECT_NEAR(c.verticalStepsFromDistance(1.0), 72.59, 1e-9);
  EXPECT_NEAR(c.verticalStepsFromDistance(0.0), 483.29, 1e-9);
  EXPECT_NEAR(c.verticalDistanceFromSteps(277.94), 0.5, 1e-12);
  EXPECT_NEAR(c.verticalDistanceFromSteps(0.0), 483.29 / 410.7, 1e-12);
  EXPECT_EQ(c.targetSteps(Axis::kVertical, 0.5), 278);
  EXPECT_EQ(c.targetSteps(Axis::kVertical, 1.0), 73);
}

TEST(ManipulatorCalibration, BeltKinematicsOfTheHorizontalAxis) {
  const ManipulatorCalibration c;  // 3 mm pitch x 20 teeth / 400 steps = 0.15 mm per step
  EXPECT_NEAR(c.horizontalMetresPerStep(), 0.00015, 1e-15);
  EXPECT_EQ(c.targetSteps(Axis::kHorizontal, 0.3), 2000);
  EXPECT_NEAR(c.horizontalExtensionFromSteps(4000), 0.6, 1e-12);
}

TEST(ManipulatorCalibration, AxisLimitsAreEnforced) {
  const ManipulatorCalibration c;
  bool clamped = false;
  EXPECT_EQ(c.targetSteps(Axis::kVertical, 0.1, &clamped), 360);  // clamped to 0.30 m: 360.08
  EXPECT_TRUE(clamped);
  EXPECT_EQ(c.targetSteps(Axis::kVertical, 2.0, &clamped), std::lround(-410.7 * 1.17 + 483.29));
  EXPECT_TRUE(clamped);
  EXPECT_EQ(c.targetSteps(Axis::kHorizontal, 0.9, &clamped), 4000);
  EXPECT_TRUE(clamped);
  EXPECT_EQ(c.targetSteps(Axis::kHorizontal, -0.1, &clamped), 0);
  EXPECT_TRUE(clamped);
  EXPECT_EQ(c.targetSteps(Axis::kHorizontal, std::nan(""), &clamped), 0);
  EXPECT_TRUE(clamped);
  c.targetSteps(Axis::kHorizontal, 0.2, &clamped);
  EXPECT_FALSE(clamped);
}

TEST(ManipulatorCalibration, RelativeMovesAndChunking) {
  std::int32_t remaining = -1;
  StepMove move = ManipulatorCalibration::moveBetween(Axis::kVertical, 100, 30, &remaining);
  EXPECT_FALSE(move.positive);
  EXPECT_EQ(move.steps, 70);
  EXPECT_EQ(remaining, 0);
  move = ManipulatorCalibration::moveBetween(Axis::kHorizontal, 0, 70000, &remaining);
  EXPECT_TRUE(move.positive);
  EXPECT_EQ(move.steps, 65535);
  EXPECT_EQ(remaining, 70000 - 65535);
}

TEST(ManipulatorCalibration, CheckNamesTheKey) {
  ManipulatorCalibration c;
  EXPECT_EQ(c.check(), "");
  c.pulley_teeth = 0.0;
  EXPECT_NE(c.check().find("pulley_teeth"), std::string::npos);
  c = ManipulatorCalibration();
  c.vertical_min_distance_m = 2.0;
  EXPECT_NE(c.check().find("vertical_min_distance_m"), std::string::npos);
  c = ManipulatorCalibration();
  c.vertical_slope_steps_per_m = 0.0;
  EXPECT_NE(c.check().find("vertical_slope_steps_per_m"), std::string::npos);
}

TEST(StepperAxisModel, MovesAtItsRateAndStopsAtEndStops) {
  StepperAxisModel axis(0, 400, 100.0, 10);
  axis.start(true, 50);
  EXPECT_FALSE(axis.step(0.25));  // 25 steps
  EXPECT_EQ(axis.positionSteps(), 35);
  EXPECT_TRUE(axis.step(0.3));  // the remaining 25 steps
  EXPECT_EQ(axis.positionSteps(), 60);
  EXPECT_FALSE(axis.moving());
  EXPECT_FALSE(axis.limitHit());
  axis.start(false, 1000);
  for (int i = 0; i < 100 && axis.moving(); ++i) axis.step(0.1);
  EXPECT_EQ(axis.positionSteps(), 0);
  EXPECT_TRUE(axis.limitHit());
}
