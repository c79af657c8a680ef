// RoverSerialBridge: the serial controllers' byte protocols in front of the MuJoCo rover.
#include <gtest/gtest.h>

#include <cmath>

#include "cotton_harvester/control/manipulator_protocol.h"
#include "cotton_harvester/control/navigation_protocol.h"
#include "cotton_harvester_sim/harvest_run.h"
#include "cotton_harvester_sim/rover_serial_bridge.h"

using namespace cotton_harvester;

namespace {

sim::RoverSimParams shortRow() {
  sim::RoverSimParams p = sim::pottedConfig(5).sim;
  p.row.plants = 1;
  return p;
}

sim::SerialBridgeParams bridgeParams(const sim::RoverSimParams& p) {
  sim::SerialBridgeParams b;
  b.calibration = sim::simArmCalibration(p.geometry);
  b.pot_noise_counts = 0.0;
  return b;
}

void drive(sim::RoverSerialBridge* bridge, std::uint8_t pwm) {
  control::DriveCommand c;
  c.pwm = pwm;
  const auto bytes = control::encodeDriveCommand(c);
  bridge->receiveNavigation(bytes.data(), bytes.size());
}

/// Runs the bridge for `seconds` with a drive command every telemetry frame (pwm < 0: no commands); returns the
/// telemetry frames received and appends the manipulator's reports.
std::vector<control::Telemetry> run(sim::RoverSerialBridge* bridge, double seconds, int pwm,
                                    std::vector<control::ManipulatorReport>* reports = nullptr) {
  control::NavigationFrameParser telemetry;
  control::ManipulatorFrameParser manip(0xB0);
  std::vector<control::Telemetry> out;
  const int steps = static_cast<int>(std::lround(seconds / 0.002));
  for (int i = 0; i < steps; ++i) {
    const auto o = bridge->advance(0.002);
    telemetry.push(o.navigation.data(), o.navigation.size());
    for (const auto& t : telemetry.takeTelemetry()) {
      out.push_back(t);
      if (pwm >= 0) drive(bridge, static_cast<std::uint8_t>(pwm));
    }
    for (const auto& f : manip.push(o.manipulator.data(), o.manipulator.size())) {
      control::ManipulatorReport r;
      if (reports && control::decodeReport(f, &r)) reports->push_back(r);
    }
  }
  return out;
}

}  // namespace

TEST(RoverSerialBridge, DriveThroughTheFramesMovesTheSimulatedRoverAndTheEncoderReportsIt) {
  const sim::RoverSimParams p = shortRow();
  sim::RoverSim s(p);
  sim::RoverSerialBridge bridge(s, bridgeParams(p));
  const Eigen::Vector3d start = s.roverPosition();
  // Inside the deadband: telemetry at 50 Hz, no motion.
  auto frames = run(&bridge, 1.0, 95);
  EXPECT_NEAR(frames.size(), 50u, 1u);
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(frames.back().encoder_count, 0);
  EXPECT_FALSE(frames.back().watchdog_stop);
  EXPECT_NEAR(frames.back().pot_counts, 512, 1);  // straight
  // Forward past the band for 4 s.
  frames = run(&bridge, 4.0, 112);
  const double travelled = (s.roverPosition() - start).x();
  EXPECT_GT(travelled, 0.3);
  EXPECT_NEAR(frames.back().encoder_count * p.drive.metres_per_pulse, travelled, 0.03 * travelled + 0.005);
  EXPECT_EQ(frames.back().encoder_count, s.encoderCount());
  // No more commands: the watchdog stops the drive within 0.5 s and says so.
  frames = run(&bridge, 3.0, -1);
  EXPECT_TRUE(frames.back().watchdog_stop);
  EXPECT_DOUBLE_EQ(bridge.commandedPwm(), 90.0);
  const std::int32_t stopped = frames.back().encoder_count;
  run(&bridge, 1.0, -1);
  EXPECT_NEAR(s.encoderCount(), stopped, 1);  // standing: at most one pulse of the wheels settling
  EXPECT_EQ(s.divergences(), 0);
}

TEST(RoverSerialBridge, ArmMovesByTheStepCommandsAndTheVacuumByTheBrush) {
  const sim::RoverSimParams p = shortRow();
  sim::RoverSim s(p);
  const sim::SerialBridgeParams b = bridgeParams(p);
  sim::RoverSerialBridge bridge(s, b);
  // Query: both counters, where the simulated arm starts (0.35 m extension, 1.20 m below the camera).
  control::ManipulatorCommand query;
  query.kind = control::ManipulatorCommand::Kind::kQuery;
  const auto q = control::encodeCommand(query);
  const auto reply = bridge.receiveManipulator(q.data(), q.size());
  ASSERT_EQ(reply.size(), 8u);
  control::ManipulatorFrameParser parser(0xB0);
  const auto frames = parser.push(reply.data(), reply.size());
  ASSERT_EQ(frames.size(), 2u);
  control::ManipulatorReport h, v;
  ASSERT_TRUE(control::decodeReport(frames[0], &h));
  ASSERT_TRUE(control::decodeReport(frames[1], &v));
  EXPECT_NEAR(b.calibration.horizontalExtensionFromSteps(h.position_steps), 0.35, 0.001);
  EXPECT_NEAR(b.calibration.verticalDistanceFromSteps(v.position_steps), 1.20, 0.003);

  // Down to 1.60 m (eq. 7: 164 steps fewer) and out by 0.15 m (1000 steps), by relative moves.
  control::ManipulatorCommand down;
  down.kind = control::ManipulatorCommand::Kind::kMove;
  down.move = {control::Axis::kVertical, false, 164};
  control::ManipulatorCommand out = down;
  out.move = {control::Axis::kHorizontal, true, 1000};
  for (const auto& c : {down, out}) {
    const auto f = control::encodeCommand(c);
    bridge.receiveManipulator(f.data(), f.size());
  }
  std::vector<control::ManipulatorReport> reports;
  run(&bridge, 2.0, 90, &reports);
  const double depth = b.calibration.verticalDistanceFromSteps(v.position_steps - 164);
  EXPECT_NEAR(s.verticalPosition(), depth, 1e-6);
  EXPECT_NEAR(depth, 1.60, 0.003);
  EXPECT_NEAR(s.horizontalPosition(), b.calibration.horizontalExtensionFromSteps(h.position_steps + 1000), 1e-6);
  EXPECT_NEAR(s.horizontalPosition(), 0.50, 0.001);
  EXPECT_FALSE(s.armMoving());
  // Reports while moving and one at the end of each move, with the final counters.
  ASSERT_GE(reports.size(), 4u);
  bool h_final = false, v_final = false;
  for (const auto& r : reports) {
    if (r.moving) continue;
    if (r.target == control::ManipulatorReport::Target::kHorizontal)
      h_final = r.position_steps == h.position_steps + 1000;
    if (r.target == control::ManipulatorReport::Target::kVertical) v_final = r.position_steps == v.position_steps - 164;
  }
  EXPECT_TRUE(h_final);
  EXPECT_TRUE(v_final);

  control::ManipulatorCommand brush;
  brush.kind = control::ManipulatorCommand::Kind::kBrush;
  brush.brush_on = true;
  const auto on = control::encodeCommand(brush);
  EXPECT_EQ(bridge.receiveManipulator(on.data(), on.size()).size(), 4u);
  run(&bridge, 0.01, 90);
  EXPECT_TRUE(s.vacuum());
  // Garbage on the link is skipped, the next frame still understood.
  const std::uint8_t junk[] = {0x00, 0xFF, 0xA3};
  bridge.receiveManipulator(junk, sizeof(junk));
  brush.brush_on = false;
  const auto off = control::encodeCommand(brush);
  bridge.receiveManipulator(off.data(), off.size());
  run(&bridge, 0.01, 90);
  EXPECT_FALSE(s.vacuum());
  EXPECT_GT(bridge.rejectedBytes(), 0u);
}

TEST(RoverSerialBridge, RejectsBadParameters) {
  const sim::RoverSimParams p = shortRow();
  sim::RoverSim s(p);
  sim::SerialBridgeParams b = bridgeParams(p);
  b.telemetry_period_s = 0.0;
  EXPECT_THROW(sim::RoverSerialBridge(s, b), std::invalid_argument);
  b = bridgeParams(p);
  b.calibration.pulley_teeth = 0.0;
  EXPECT_THROW(sim::RoverSerialBridge(s, b), std::invalid_argument);
  b = bridgeParams(p);
  b.pot_noise_counts = std::nan("");
  EXPECT_THROW(sim::RoverSerialBridge(s, b), std::invalid_argument);
}
