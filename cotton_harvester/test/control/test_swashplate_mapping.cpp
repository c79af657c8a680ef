#include <gtest/gtest.h>

#include <cmath>

#include "cotton_harvester/control/swashplate_mapping.h"

using cotton_harvester::control::SwashplateMapping;

// eq. 8 of the paper, values worked out by hand: u = 10 (x - 98) on 98..108, u = 10 (x - 80) on 70..80.
TEST(SwashplateMapping, EffortToPwmByValue) {
  const SwashplateMapping m;
  EXPECT_DOUBLE_EQ(m.pwmFromEffort(0.0), 90.0);
  EXPECT_DOUBLE_EQ(m.pwmFromEffort(100.0), 108.0);
  EXPECT_DOUBLE_EQ(m.pwmFromEffort(50.0), 103.0);
  EXPECT_NEAR(m.pwmFromEffort(1.0), 98.1, 1e-12);
  EXPECT_DOUBLE_EQ(m.pwmFromEffort(-100.0), 70.0);
  EXPECT_DOUBLE_EQ(m.pwmFromEffort(-50.0), 75.0);
  EXPECT_NEAR(m.pwmFromEffort(-1.0), 79.9, 1e-12);
  EXPECT_DOUBLE_EQ(m.pwmFromEffort(250.0), 108.0);
  EXPECT_DOUBLE_EQ(m.pwmFromEffort(-250.0), 70.0);
  EXPECT_DOUBLE_EQ(m.pwmFromEffort(std::nan("")), 90.0);
}

TEST(SwashplateMapping, PwmToEffortIsEquationEight) {
  const SwashplateMapping m;
  EXPECT_DOUBLE_EQ(m.effortFromPwm(108.0), 100.0);
  EXPECT_DOUBLE_EQ(m.effortFromPwm(103.0), 50.0);
  EXPECT_DOUBLE_EQ(m.effortFromPwm(98.0), 0.0);
  EXPECT_DOUBLE_EQ(m.effortFromPwm(80.0), 0.0);
  EXPECT_DOUBLE_EQ(m.effortFromPwm(75.0), -50.0);
  EXPECT_DOUBLE_EQ(m.effortFromPwm(70.0), -100.0);
  for (double deadband : {81.0, 85.0, 90.0, 97.9}) EXPECT_DOUBLE_EQ(m.effortFromPwm(deadband), 0.0) << deadband;
  EXPECT_DOUBLE_EQ(m.effortFromPwm(120.0), 100.0);  // beyond the mapped range: saturated
  EXPECT_DOUBLE_EQ(m.effortFromPwm(65.0), -100.0);
}

TEST(SwashplateMapping, NeverCommandsInsideTheDeadband) {
  const SwashplateMapping m;
  for (double u = -100.0; u <= 100.0; u += 0.25) {
    const double pwm = m.pwmFromEffort(u);
    EXPECT_TRUE(pwm == 90.0 || pwm >= 98.0 || pwm <= 80.0) << "u " << u << " pwm " << pwm;
    if (u != 0.0) EXPECT_NEAR(m.effortFromPwm(pwm), u, 1e-9);
  }
}

TEST(SwashplateMapping, CheckNamesBadValues) {
  SwashplateMapping m;
  EXPECT_STREQ(m.check(), "");
  m.forward_max_pwm = 97.0;
  EXPECT_NE(std::string(m.check()).find("forward_max_pwm"), std::string::npos);
  m = SwashplateMapping();
  m.effort_limit = 0.0;
  EXPECT_NE(std::string(m.check()).find("effort_limit"), std::string::npos);
}
