#include <gtest/gtest.h>

#include <cmath>

#include "test_robots.h"
#include "thorvald_base/angles.h"
#include "thorvald_base/simulated_drive.h"

using namespace thorvald_base;

TEST(SimulatedDrive, PropulsionRampsAtTheAccelerationLimit) {
  SimulatedDrive d(test::drive(0, 0, 0));
  d.setCommand({5.0, 0.0});  // 1 m/s at r = 0.2
  d.update(0.0);
  d.update(0.4);  // 1.5 m/s^2 for 0.4 s = 0.6 m/s
  EXPECT_NEAR(d.feedback().wheel_speed_radps * 0.2, 0.6, 0.002);
  d.update(1.0);
  EXPECT_NEAR(d.feedback().wheel_speed_radps, 5.0, 0.01);
}

TEST(SimulatedDrive, SteeringMovesAtItsRateWithinLimits) {
  SimulatedDrive d(test::drive(0, 0, 0));
  d.setCommand({0.0, 1.0});
  d.update(0.0);
  d.update(0.1);  // 4 rad/s
  EXPECT_NEAR(d.feedback().steering_rad, 0.4, 1e-3);
  d.setCommand({0.0, 10.0});  // beyond the limit: held at str_lim
  d.update(2.0);
  EXPECT_NEAR(d.feedback().steering_rad, 3.078027759, 1e-3);
}

TEST(SimulatedDrive, ReadingsAreQuantisedLikeTheEncoders) {
  SimulatedDrive d(test::drive(0, 0, 0));
  d.setCommand({0.3, 0.1234});
  d.update(0.0);
  d.update(3.0);
  const double rpm = d.feedback().wheel_speed_radps * 42 * 30 / kPi;
  EXPECT_NEAR(rpm, std::round(rpm), 1e-9);
  const double count = 2 * kPi / (4 * 1024 * 42.8571429);
  const double counts = d.feedback().steering_rad / count;
  EXPECT_NEAR(counts, std::round(counts), 1e-6);
  EXPECT_NEAR(d.feedback().steering_rad, 0.1234, count);
}

TEST(SimulatedDrive, RadiusErrorAndSlipShowInTruthNotReading) {
  SimulatedDriveOptions o;
  o.radius_error = 0.01;
  o.slip_ratio = 0.2;
  o.slip_fraction = 1.0;
  o.quantize = false;
  SimulatedDrive d(test::drive(0, 0, 0), o);
  d.setCommand({2.0, 0.0});
  d.update(0.0);
  d.update(5.0);
  EXPECT_NEAR(d.truth().wheel_speed_radps, 2.0 * 1.01, 1e-9);    // rolls 1% further than r_wheel says
  EXPECT_NEAR(d.feedback().wheel_speed_radps, 2.0 * 1.2, 1e-9);  // slipping: reads 20% faster
}

TEST(SimulatedDrive, FaultAndHomingStopPropulsion) {
  SimulatedDrive d(test::drive(0, 0, 0));
  d.setCommand({2.0, 0.5});
  d.update(0.0);
  d.setFault(true);
  d.update(2.0);
  EXPECT_TRUE(d.status().fault);
  EXPECT_NEAR(d.feedback().wheel_speed_radps, 0.0, 0.01);
  d.setFault(false);
  ASSERT_TRUE(d.startHoming());
  d.update(3.0);
  EXPECT_TRUE(d.status().homing);
  EXPECT_NEAR(d.feedback().steering_rad, 0.0, 1e-3);
  d.update(10.0);
  EXPECT_FALSE(d.status().homing);
  EXPECT_NEAR(d.feedback().steering_rad, 0.5, 1e-3);
}
