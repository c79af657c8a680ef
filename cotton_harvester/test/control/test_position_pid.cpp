#include <gtest/gtest.h>

#include <cmath>

#include "cotton_harvester/control/position_pid.h"

using cotton_harvester::control::PidGains;
using cotton_harvester::control::PositionPid;

TEST(PositionPid, TermsByValue) {
  PidGains gains;  // Kp 0.7, Ki 0.04, Kd 5.0
  gains.derivative_filter_s = 0.0;
  PositionPid pid(gains);
  // First step: no derivative history. e = 10 pulses, dt 0.1 s: 0.7*10 + 0.04*10*0.1 = 7.04.
  EXPECT_NEAR(pid.update(10.0, 0.0, 0.1), 7.04, 1e-12);
  EXPECT_NEAR(pid.integral(), 0.04, 1e-12);
  // Measurement moves 2 pulses in 0.1 s: e = 8; P 5.6, I 0.04 + 0.032 = 0.072, D -5*20 = -100 -> -94.328.
  EXPECT_NEAR(pid.update(10.0, 2.0, 0.1), 5.6 + 0.072 - 100.0, 1e-9);
}

TEST(PositionPid, DerivativeIsLowPassed) {
  PidGains gains{0.0, 0.0, 5.0, -100.0, 100.0, 0.1};
  PositionPid pid(gains);
  pid.update(0.0, 0.0, 0.1);
  // Rate 20 pulses/s, filter weight 1 - exp(-0.1 / 0.1) = 0.63212: D = -5 * 20 * 0.63212 = -63.212.
  EXPECT_NEAR(pid.update(0.0, 2.0, 0.1), -5.0 * 20.0 * (1.0 - std::exp(-1.0)), 1e-9);
  // Steady rate: the filtered value approaches the true one.
  double u = 0.0;
  for (int i = 2; i < 100; ++i) u = pid.update(0.0, 2.0 * i, 0.1);
  EXPECT_NEAR(u, -100.0, 1e-6);  // -5 * 20 = -100 (at the limit)
}

TEST(PositionPid, NoDerivativeKickOnSetpointChange) {
  PositionPid pid(PidGains{0.0, 0.0, 5.0, -100.0, 100.0});
  pid.update(0.0, 3.0, 0.02);
  EXPECT_DOUBLE_EQ(pid.update(500.0, 3.0, 0.02), 0.0);  // derivative on the measurement only
}

TEST(PositionPid, OutputIsClampedAndIntegralDoesNotWindUp) {
  PositionPid pid;
  for (int i = 0; i < 1000; ++i) EXPECT_LE(pid.update(1000.0, 0.0, 0.02), 100.0);
  // Saturated high with a positive error the whole time: the integral never grew.
  EXPECT_DOUBLE_EQ(pid.integral(), 0.0);
  // Without anti-windup it would hold 0.04 * 1000 * 20 s = 800: check the opposite direction.
  for (int i = 0; i < 1000; ++i) EXPECT_GE(pid.update(-1000.0, 0.0, 0.02), -100.0);
  EXPECT_DOUBLE_EQ(pid.integral(), 0.0);
}

TEST(PositionPid, IntegralRemovesAConstantOffsetWhenNotSaturated) {
  PositionPid pid(PidGains{0.1, 0.5, 0.0, -100.0, 100.0});
  // e = 20 for 10 s: the integral grows by 0.2 per step until P (2) + I reaches the limit, then holds.
  for (int i = 0; i < 500; ++i) pid.update(20.0, 0.0, 0.02);
  EXPECT_NEAR(pid.integral(), 97.9, 0.1 + 1e-9);
  EXPECT_NEAR(pid.lastOutput(), 99.9, 0.1 + 1e-9);
}

TEST(PositionPid, RejectsBadInputKeepingTheLastOutput) {
  PositionPid pid;
  const double u = pid.update(10.0, 0.0, 0.1);
  EXPECT_DOUBLE_EQ(pid.update(std::nan(""), 0.0, 0.1), u);
  EXPECT_DOUBLE_EQ(pid.update(10.0, INFINITY, 0.1), u);
  EXPECT_DOUBLE_EQ(pid.update(10.0, 0.0, 0.0), u);
  EXPECT_DOUBLE_EQ(pid.update(10.0, 0.0, -1.0), u);
  pid.reset();
  EXPECT_DOUBLE_EQ(pid.integral(), 0.0);
  EXPECT_DOUBLE_EQ(pid.lastOutput(), 0.0);
}
