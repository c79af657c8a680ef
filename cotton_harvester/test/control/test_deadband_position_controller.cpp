#include <cmath>

#include <gtest/gtest.h>

#include "cotton_harvester/control/deadband_position_controller.h"
#include "cotton_harvester/control/step_response.h"

using namespace cotton_harvester::control;

TEST(DeadbandPositionController, InverseDeadbandMapSkipsTheBand) {
  const DeadbandPositionController controller;
  const DeadbandControllerParams p;
  EXPECT_DOUBLE_EQ(controller.pwmForSpeed(0.0), 90.0);
  // Any wanted speed, however small, lands past the deadband's edge on its side.
  EXPECT_GT(controller.pwmForSpeed(1e-4), 98.0);
  EXPECT_LT(controller.pwmForSpeed(-1e-4), 80.0);
  EXPECT_NEAR(controller.pwmForSpeed(0.1), 98.0 + 0.1 / p.forward_mps_per_pwm, 1e-9);
  EXPECT_NEAR(controller.pwmForSpeed(-0.1), 80.0 - 0.1 / p.reverse_mps_per_pwm, 1e-9);
  EXPECT_DOUBLE_EQ(controller.pwmForSpeed(10.0), p.pwm_max);
  EXPECT_DOUBLE_EQ(controller.pwmForSpeed(-10.0), p.pwm_min);
}

TEST(DeadbandPositionController, BadInputHoldsNeutral) {
  DeadbandPositionController controller;
  controller.setTarget(1.0);
  EXPECT_DOUBLE_EQ(controller.update(std::nan(""), 0.02), 90.0);
  EXPECT_DOUBLE_EQ(controller.update(0.0, 0.0), 90.0);
  controller.setTarget(std::nan(""));
  EXPECT_DOUBLE_EQ(controller.targetM(), 1.0);
}

TEST(DeadbandPositionController, RejectsUnsoundParameters) {
  DeadbandControllerParams p;
  EXPECT_EQ(p.check(), "");
  p.forward_edge_pwm = 85.0;  // below neutral
  EXPECT_NE(p.check(), "");
  p = DeadbandControllerParams{};
  p.restart_tolerance_m = 0.001;  // below the stop tolerance
  EXPECT_NE(p.check(), "");
}

// On the simulated drive (deadband 80-98, 12 PWM/s actuator, 0.4 s flow lag) through the serial frames: every
// step forward and back ends within the 5 cm band, sooner and with less overshoot than the paper's PID on the
// same drive. Tolerances: the goals, overshoot <= 0.05 m and settling <= 10 s.
TEST(DeadbandPositionController, StepsSettleFasterThanThePapersPid) {
  const SimulatedNavigationParams drive;
  RoverControllerParams paper;
  paper.position_control = PositionControl::kPaperPid;
  const StepResponse paper_1m = simulateStep(paper, drive, 1.0, 60.0, 0.05);
  for (const double step : {0.3, 1.0, 2.0, -0.3, -1.0, -2.0}) {
    const StepResponse response = simulateStep(RoverControllerParams{}, drive, step, 30.0, 0.05);
    SCOPED_TRACE(step);
    ASSERT_GE(response.settling_s, 0.0);
    EXPECT_LE(response.settling_s, 10.0);
    EXPECT_LE(std::abs(response.final_error_m), 0.05);
    EXPECT_LE(response.overshoot_m, 0.05);
    if (step == 1.0) {
      EXPECT_LT(response.settling_s, paper_1m.settling_s);
      EXPECT_LT(response.overshoot_m, paper_1m.overshoot_m);
    }
  }
}
