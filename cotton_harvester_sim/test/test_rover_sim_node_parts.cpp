// The parts of mujoco_rover_sim without ROS: what the stack reports, the scorer, the serial device emulation.
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "cotton_harvester/control/navigation_protocol.h"
#include "cotton_harvester/control/serial_port.h"
#include "cotton_harvester_sim/harvest_run.h"
#include "cotton_harvester_sim/harvest_scorer.h"
#include "cotton_harvester_sim/rover_device_emulator.h"
#include "cotton_harvester_sim/stack_run_report.h"

using namespace cotton_harvester;
using namespace cotton_harvester::sim;

TEST(StackRunReport, StartsOnTheFirstRunningStatusAndEndsWhenTheStackSaysSo) {
  StackRunReport report;
  EXPECT_EQ(report.check(5.0, 1.0, 100.0, 10.0), StackRunState::kWaiting);
  EXPECT_FALSE(report.onStatus(false, 1.0));
  EXPECT_TRUE(report.onStatus(true, 2.5));
  EXPECT_FALSE(report.onStatus(true, 3.0));  // only the first
  EXPECT_EQ(report.check(5.0, 1.0, 100.0, 10.0), StackRunState::kRunning);
  report.onMetrics("running", {{"detected", "4"}, {"asr_pct", "n/a"}, {"time_s", "12.5"}});
  EXPECT_EQ(report.check(6.0, 1.0, 100.0, 10.0), StackRunState::kRunning);
  report.onMetrics("ended: finished", {{"picked", "3"}});
  EXPECT_EQ(report.check(7.0, 1.0, 100.0, 10.0), StackRunState::kEnded);
  const StackFigures figures = report.figures();
  EXPECT_TRUE(figures.started);
  EXPECT_EQ(figures.started_at_s, 2.5);
  EXPECT_EQ(figures.outcome, "finished");
  EXPECT_EQ(figures.values.at("detected"), 4.0);
  EXPECT_EQ(figures.values.at("picked"), 3.0);
  EXPECT_EQ(figures.values.at("time_s"), 12.5);
  EXPECT_EQ(figures.values.count("asr_pct"), 0u);
}

TEST(StackRunReport, TimeLimitAndNoStart) {
  StackRunReport late;
  late.onMetrics("ended: finished", {});  // before the start: not the end of this run
  EXPECT_EQ(late.check(1.0, 11.0, 100.0, 10.0), StackRunState::kNoStart);
  StackRunReport slow;
  slow.onStatus(true, 2.0);
  EXPECT_EQ(slow.check(102.0, 500.0, 100.0, 10.0), StackRunState::kRunning);  // exactly at the limit
  EXPECT_EQ(slow.check(102.5, 500.0, 100.0, 10.0), StackRunState::kEnded);
  EXPECT_EQ(slow.figures().outcome, "time_limit");
}

namespace {

RoverTruth fourBolls() {
  RoverTruth truth;
  truth.bolls.resize(4);
  for (int i = 0; i < 4; ++i) {
    truth.bolls[static_cast<std::size_t>(i)].plant = i / 2;
    truth.bolls[static_cast<std::size_t>(i)].centre = Eigen::Vector3d(0.5 * i, 0.1, 0.6);
  }
  truth.bolls[0].captured = truth.bolls[3].captured = true;
  truth.bolls[1].closest_vacuum_m = 0.034;
  truth.bolls_captured = 2;
  truth.rover_position = Eigen::Vector3d(3.0, 4.0, 0.0);
  truth.time_s = 80.0;
  return truth;
}

}  // namespace

TEST(HarvestScorer, CountsTheTruthAgainstWhatTheStackReported) {
  const HarvestScorer scorer({true, true, false, true}, Eigen::Vector3d::Zero());
  StackFigures stack;
  stack.started = true;
  stack.started_at_s = 10.0;
  stack.outcome = "finished";
  stack.values = {{"detected", 4}, {"reached", 3}, {"picked", 3}, {"time_s", 50.0}, {"ee_fallback_frames", 2}};
  const HarvestScore score = scorer.score(stack, fourBolls());
  EXPECT_EQ(score.outcome, "finished");
  EXPECT_EQ(score.counts.bolls_present, 4);
  EXPECT_EQ(score.counts.picked, 2);
  EXPECT_EQ(score.counts.detected, 4);
  EXPECT_EQ(score.counts.reached, 3);
  EXPECT_EQ(score.machine_picked, 3);
  EXPECT_EQ(score.counts.time_s, 50.0);  // the machine's own
  EXPECT_DOUBLE_EQ(score.counts.distance_m, 5.0);
  EXPECT_EQ(score.reachable, 3);
  EXPECT_EQ(score.reachable_picked, 2);
  EXPECT_EQ(score.ee_fallback_frames, 2.0);
  ASSERT_TRUE(score.metrics.action_success_pct);
  EXPECT_DOUBLE_EQ(*score.metrics.action_success_pct, 50.0);
  ASSERT_EQ(score.missed.size(), 2u);
  EXPECT_EQ(score.missed[0].index, 1u);
  EXPECT_TRUE(score.missed[0].reachable);
  EXPECT_EQ(score.missed[1].index, 2u);
  EXPECT_FALSE(score.missed[1].reachable);

  const auto lines = missedBollLines("sim", score);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "sim: missed boll 1 (plant 0, x 0.50 y 0.10 z 0.60); nozzle closest 3.4 cm");
  EXPECT_EQ(lines[1], "sim: missed boll 2 (plant 1, x 1.00 y 0.10 z 0.60) unreachable; nozzle closest -1.0 cm");
  SimRunFigures run;
  run.sim_s = 80.0;
  run.wall_s = 40.0;
  run.frames = 7;
  const std::string summary = summaryLine("sim", score, run);
  EXPECT_EQ(summary.rfind("sim: finished; bolls 4 (reachable 3), detected 4, reached 3, picked 2 (machine: 3);", 0), 0u)
      << summary;
  EXPECT_NE(summary.find("7 frames; 2.00x real time"), std::string::npos) << summary;
}

TEST(HarvestScorer, AtTheTimeLimitTheRunLastsSinceTheStart) {
  const HarvestScorer scorer({true, true, true, true}, Eigen::Vector3d(3.0, 0.0, 0.0));
  StackFigures stack;
  stack.started = true;
  stack.started_at_s = 10.0;
  stack.outcome = "time_limit";
  stack.values = {{"time_s", 50.0}};
  const HarvestScore score = scorer.score(stack, fourBolls());
  EXPECT_EQ(score.counts.time_s, 70.0);
  EXPECT_DOUBLE_EQ(score.counts.distance_m, 4.0);
  EXPECT_EQ(score.counts.detected, 0);  // not reported
}

namespace {

RoverSimParams oneBollRow() {
  RoverSimParams p = pottedConfig(5).sim;
  p.row.plants = 1;
  return p;
}

SerialBridgeParams bridgeParams(const RoverSimParams& p) {
  SerialBridgeParams b;
  b.calibration = simArmCalibration(p.geometry);
  b.pot_noise_counts = 0.0;
  return b;
}

/// Reads what arrives on the host's port for up to `ms`.
std::vector<std::uint8_t> readFor(control::SerialPort* port, int ms) {
  std::vector<std::uint8_t> bytes;
  std::uint8_t buffer[512];
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  while (std::chrono::steady_clock::now() < end) {
    const long n = port->read(buffer, sizeof(buffer), 10);
    if (n > 0) bytes.insert(bytes.end(), buffer, buffer + n);
  }
  return bytes;
}

}  // namespace

TEST(RoverDeviceEmulator, TheNavigationControllerTalksThroughItsSerialLink) {
  const std::string dir = "/tmp/cotton_harvester_emulator_test_" + std::to_string(::getpid());
  const RoverSimParams p = oneBollRow();
  RoverSim sim(p);
  RoverDeviceEmulator devices(sim, bridgeParams(p), dir + "/manipulator", dir + "/navigation");
  control::SerialPort host;
  ASSERT_TRUE(host.open(dir + "/navigation", 115200)) << host.lastError();

  const double start = sim.time();
  const auto frames = devices.advance(0.1, p.timestep_s);
  EXPECT_NEAR(sim.time() - start, 0.1, 1e-9);
  ASSERT_FALSE(frames.navigation.empty());  // telemetry at 50 Hz
  devices.send(frames, 0.0, [] { return true; });
  control::NavigationFrameParser parser;
  const auto received = readFor(&host, 100);
  parser.push(received.data(), received.size());
  EXPECT_GE(parser.takeTelemetry().size(), 4u);

  // Lockstep: without a drive command in answer the wait times out and is counted.
  devices.send(devices.advance(0.02, p.timestep_s), 0.02, [] { return true; });
  EXPECT_EQ(devices.lockstepTimeouts(), 1);
  EXPECT_EQ(devices.bridge().driveCommands(), 0u);

  control::DriveCommand command;
  command.pwm = 100;
  const auto bytes = control::encodeDriveCommand(command);
  ASSERT_TRUE(host.write(bytes.data(), bytes.size()));
  for (int i = 0; i < 100 && devices.bridge().driveCommands() == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    devices.serveLinks();
  }
  EXPECT_EQ(devices.bridge().driveCommands(), 1u);
  EXPECT_EQ(devices.rejectedBytes(), 0u);
}

TEST(RoverDeviceEmulator, ALinkThatCannotBeMadeThrows) {
  const RoverSimParams p = oneBollRow();
  RoverSim sim(p);
  EXPECT_THROW(RoverDeviceEmulator(sim, bridgeParams(p), "/proc/no_such_dir/manipulator", "/proc/no_such_dir/nav"),
               std::runtime_error);
}
