#include <gtest/gtest.h>

#include <cmath>

#include "cotton_harvester/control/hydrostatic_drive_model.h"
#include "cotton_harvester/control/rover_controller.h"
#include "cotton_harvester/control/simulated_controllers.h"
#include "cotton_harvester/control/step_response.h"

using namespace cotton_harvester::control;

TEST(HydrostaticDriveModel, DeadbandSlewAndLag) {
  HydrostaticDriveModel drive;  // deadband 80..98, 0.5 m/s at 120, 12 PWM/s, lag 0.4 s
  for (int i = 0; i < 1000; ++i) drive.step(95.0, false, false, 0.01);  // inside the deadband
  EXPECT_DOUBLE_EQ(drive.positionM(), 0.0);
  EXPECT_NEAR(drive.actuatorPwm(), 95.0, 1e-9);
  HydrostaticDriveModel fresh;
  fresh.step(108.0, false, false, 0.5);  // actuator slews: 90 -> 96 in 0.5 s
  EXPECT_NEAR(fresh.actuatorPwm(), 96.0, 1e-9);
  for (int i = 0; i < 1000; ++i) fresh.step(108.0, false, false, 0.01);
  EXPECT_NEAR(fresh.speedMps(), 0.5 * (108.0 - 98.0) / (120.0 - 98.0), 1e-6);
  EXPECT_NEAR(fresh.flowSpeed(72.5), -0.5 * 7.5 / 15.0, 1e-12);
  EXPECT_EQ(HydrostaticDriveModel().encoderCount(), 0);
}

TEST(HydrostaticDriveModel, EncoderCountsPulsesOf1p8mm) {
  HydrostaticDriveParams params;
  params.flow_time_constant_s = 0.0;
  params.actuator_rate_pwm_per_s = 1e6;
  HydrostaticDriveModel drive(params);
  // 120 PWM: 0.5 m/s; 1.8 s -> 0.9 m -> 500 pulses.
  for (int i = 0; i < 180; ++i) drive.step(120.0, false, false, 0.01);
  EXPECT_NEAR(drive.positionM(), 0.9, 1e-9);
  EXPECT_NEAR(drive.encoderCount(), 500, 1);
}

TEST(RoverController, MapsThePidOutputThroughEquationEight) {
  RoverControllerParams paper;
  paper.position_control = PositionControl::kPaperPid;
  RoverController controller(paper);
  Telemetry telemetry;
  telemetry.pot_counts = 512;
  controller.update(telemetry, 0.02);
  controller.setPositionTarget(0.018);  // 10 pulses ahead: u = 0.7 * 10 + 0.04 * 10 * 0.02 = 7.008
  const RoverOutput output = controller.update(telemetry, 0.02);
  EXPECT_NEAR(output.effort, 7.008, 1e-9);
  EXPECT_NEAR(output.pwm, 98.0 + 0.7008, 1e-9);
  EXPECT_EQ(output.command().pwm, 99);
  controller.setPositionTarget(-1.0);
  EXPECT_LT(controller.update(telemetry, 0.02).pwm, 80.0 + 1e-9);
}

// The paper's PID (second tuning) against the simulated hydrostatic drive, through the serial frames.
TEST(RoverController, StepResponseAgainstTheSimulatedDrive) {
  RoverControllerParams controller;
  controller.position_control = PositionControl::kPaperPid;
  const SimulatedNavigationParams plant;
  for (double step : {1.0, -0.5}) {
    const StepResponse r = simulateStep(controller, plant, step, 90.0, 0.05);
    ASSERT_FALSE(r.samples.empty());
    // It gets there and stays within ±5 cm ...
    EXPECT_NEAR(r.final_error_m, 0.0, 0.05) << "step " << step;
    EXPECT_GE(r.settling_s, 0.0) << "step " << step;
    EXPECT_LT(r.settling_s, 80.0) << "step " << step;
    // ... after an overshoot of the order the paper reports (18 cm).
    EXPECT_GT(r.overshoot_m, 0.02) << "step " << step;
    EXPECT_LT(r.overshoot_m, 0.35) << "step " << step;
    // The controller never parks the servo inside the deadband (only exactly at neutral).
    for (const auto& s : r.samples) ASSERT_TRUE(s.pwm == 90.0 || s.pwm >= 98.0 || s.pwm <= 80.0) << s.pwm;
  }
}

TEST(RoverController, VelocityModeTracksCmdVel) {
  SimulatedNavigationController navigation;
  RoverController controller;
  NavigationFrameParser parser;
  controller.setVelocity(0.1, 0.0);
  for (int i = 0; i < 10000; ++i) {  // 20 s at 2 ms
    const auto bytes = navigation.step(0.002);
    parser.push(bytes.data(), bytes.size());
    for (const auto& telemetry : parser.takeTelemetry()) {
      const auto frame = encodeDriveCommand(controller.update(telemetry, 0.02).command());
      navigation.receive(frame.data(), frame.size());
    }
  }
  // 0.1 m/s for 20 s is 2 m; the lagging start costs a little.
  EXPECT_NEAR(navigation.drive().positionM(), 2.0, 0.3);
  controller.holdPosition();
  EXPECT_FALSE(controller.velocityMode());
}

TEST(ArticulationController, ReachesTheTargetThroughRelays) {
  SimulatedNavigationController navigation;  // pot 5 counts/deg with ±1 count noise, 8 deg/s
  RoverController controller;
  NavigationFrameParser parser;
  controller.setArticulationTarget(20.0);
  for (int i = 0; i < 5000; ++i) {  // 10 s
    const auto bytes = navigation.step(0.002);
    parser.push(bytes.data(), bytes.size());
    for (const auto& telemetry : parser.takeTelemetry()) {
      controller.setPositionTarget(0.0);
      const auto frame = encodeDriveCommand(controller.update(telemetry, 0.02).command());
      navigation.receive(frame.data(), frame.size());
    }
  }
  EXPECT_NEAR(navigation.drive().articulationDeg(), 20.0, 1.5);
  controller.setArticulationTarget(80.0);  // beyond ±45°
  EXPECT_DOUBLE_EQ(controller.articulationTargetDeg(), 45.0);
}

TEST(ArticulationController, ProportionalDutyAndCalibration) {
  ArticulationController articulation;  // Kp 1, deadband 1°, full duty at 5°, 0.2 s period
  EXPECT_DOUBLE_EQ(articulation.angleFromPot(612.0), 20.0);
  EXPECT_DOUBLE_EQ(articulation.potFromAngle(-10.0), 462.0);
  int on = 0;
  for (int i = 0; i < 100; ++i) on += articulation.update(2.5, 0.0, 0.01).left ? 1 : 0;  // e = 2.5°: 50 %
  EXPECT_NEAR(on, 50, 2);
  on = 0;
  for (int i = 0; i < 100; ++i) on += articulation.update(-10.0, 0.0, 0.01).right ? 1 : 0;
  EXPECT_EQ(on, 100);
  const RelayCommand idle = articulation.update(0.5, 0.0, 0.01);
  EXPECT_FALSE(idle.left || idle.right);
  const RelayCommand at_limit = articulation.update(45.0, 45.5, 0.01);
  EXPECT_FALSE(at_limit.left || at_limit.right);
}

TEST(ArticulatedOdometry, StraightAndTurning) {
  ArticulatedOdometry odometry(0.91);
  odometry.update(1.0, 0.0, 1.0);
  EXPECT_NEAR(odometry.x(), 1.0, 1e-12);
  EXPECT_NEAR(odometry.yaw(), 0.0, 1e-12);
  EXPECT_NEAR(odometry.speed(), 1.0, 1e-12);
  ArticulatedOdometry turning(0.91);
  for (int i = 0; i < 100; ++i) turning.update(0.01, 30.0, 0.1);
  EXPECT_NEAR(turning.yaw(), 1.0 * std::tan(15.0 * M_PI / 180.0) / 0.91, 1e-9);
  turning.update(std::nan(""), 0.0, 0.1);
  EXPECT_TRUE(std::isfinite(turning.x()));
}

TEST(SimulatedNavigationController, WatchdogStopsWithoutCommands) {
  SimulatedNavigationController navigation;
  const auto frame = encodeDriveCommand(DriveCommand{120, false, false, 0});
  navigation.receive(frame.data(), frame.size());
  EXPECT_FALSE(navigation.watchdogStopped());
  for (int i = 0; i < 200; ++i) navigation.step(0.01);  // 2 s without a command
  EXPECT_TRUE(navigation.watchdogStopped());
  EXPECT_DOUBLE_EQ(navigation.commandedPwm(), 90.0);
  EXPECT_NEAR(navigation.drive().speedMps(), 0.0, 1e-3);
}

TEST(RoverControllerParams, CheckNamesTheKey) {
  RoverControllerParams params;
  EXPECT_EQ(params.check(), "");
  params.metres_per_pulse = 0.0;
  EXPECT_NE(params.check().find("metres_per_pulse"), std::string::npos);
  params = RoverControllerParams();
  params.articulation.kp = -1.0;
  EXPECT_NE(params.check().find("articulation kp"), std::string::npos);
}
