// The serial path end to end: host-side SerialPort <-> pseudo-terminal <-> simulated controllers,
// and what a host sees when the device vanishes.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <string>

#include "cotton_harvester/control/manipulator_protocol.h"
#include "cotton_harvester/control/navigation_protocol.h"
#include "cotton_harvester/control/serial_port.h"
#include "cotton_harvester/control/simulated_controllers.h"

using namespace cotton_harvester::control;

namespace {

std::string linkPath(const std::string& name) { return "/tmp/cotton_test_" + std::to_string(::getpid()) + "_" + name; }

/// Pumps bytes between a pseudo-terminal and a simulated manipulation controller until `done`.
template <typename Done>
bool pumpManipulator(PseudoTerminal& pty, SimulatedManipulationController& sim, SerialPort& host,
                     ManipulatorFrameParser& parser, std::vector<ManipulatorReport>* reports, Done done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  std::uint8_t buffer[256];
  while (std::chrono::steady_clock::now() < deadline) {
    long n = pty.read(buffer, sizeof(buffer));
    if (n > 0) {
      const auto reply = sim.receive(buffer, static_cast<std::size_t>(n));
      pty.write(reply.data(), reply.size());
    }
    const auto out = sim.step(0.01);  // simulated time runs faster than the wall clock here
    pty.write(out.data(), out.size());
    n = host.read(buffer, sizeof(buffer), 2);
    if (n < 0) return false;
    for (const auto& frame : parser.push(buffer, static_cast<std::size_t>(n))) {
      ManipulatorReport report;
      if (decodeReport(frame, &report)) reports->push_back(report);
    }
    if (done()) return true;
  }
  return false;
}

}  // namespace

TEST(SerialPath, ManipulatorMoveThroughAPseudoTerminal) {
  PseudoTerminal pty;
  const std::string link = linkPath("manipulator");
  ASSERT_TRUE(pty.open(link)) << pty.lastError();
  SerialPort host;
  ASSERT_TRUE(host.open(link, 115200)) << host.lastError();
  SimulatedManipulationController sim;  // vertical starts at 0 steps (1.177 m from the camera)

  const ManipulatorCalibration calibration;
  const std::int32_t target = calibration.targetSteps(Axis::kVertical, 0.5);  // 278 steps
  ManipulatorCommand command;
  command.kind = ManipulatorCommand::Kind::kMove;
  command.move = ManipulatorCalibration::moveBetween(Axis::kVertical, 0, target);
  const auto frame = encodeCommand(command);
  ASSERT_TRUE(host.write(frame.data(), frame.size()));

  ManipulatorFrameParser parser(0xB0);
  std::vector<ManipulatorReport> reports;
  ASSERT_TRUE(pumpManipulator(pty, sim, host, parser, &reports, [&reports] {
    return !reports.empty() && !reports.back().moving && reports.back().target == ManipulatorReport::Target::kVertical;
  }));
  EXPECT_EQ(reports.back().position_steps, 278);
  EXPECT_NEAR(calibration.verticalDistanceFromSteps(reports.back().position_steps), 0.5, 0.003);
  EXPECT_EQ(sim.vertical().positionSteps(), 278);
  EXPECT_GT(reports.size(), 1u);  // progress reports while it moved
  EXPECT_EQ(sim.rejectedBytes(), 0u);
}

TEST(SerialPath, NavigationTelemetryAndCommandsThroughAPseudoTerminal) {
  PseudoTerminal pty;
  const std::string link = linkPath("navigation");
  ASSERT_TRUE(pty.open(link)) << pty.lastError();
  SerialPort host;
  ASSERT_TRUE(host.open(link, 115200)) << host.lastError();
  SimulatedNavigationController sim;
  NavigationFrameParser parser;
  const auto command = encodeDriveCommand(DriveCommand{120, false, false, 1});
  std::uint8_t buffer[512];
  int telemetry_frames = 0;
  std::int32_t last_count = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline && telemetry_frames < 150) {
    ASSERT_TRUE(host.write(command.data(), command.size()));
    long n = pty.read(buffer, sizeof(buffer));
    if (n > 0) sim.receive(buffer, static_cast<std::size_t>(n));
    const auto out = sim.step(0.02);
    pty.write(out.data(), out.size());
    n = host.read(buffer, sizeof(buffer), 5);
    ASSERT_GE(n, 0) << host.lastError();
    parser.push(buffer, static_cast<std::size_t>(n));
    for (const auto& t : parser.takeTelemetry()) {
      ++telemetry_frames;
      last_count = t.encoder_count;
      EXPECT_FALSE(t.watchdog_stop);
    }
  }
  ASSERT_GE(telemetry_frames, 150);
  EXPECT_GT(sim.commandsReceived(), 100u);
  // The host's encoder count is the simulated drive's, in 1.8 mm pulses.
  EXPECT_NEAR(last_count * 0.0018, sim.drive().positionM(), 0.2);
  EXPECT_GT(sim.drive().positionM(), 0.5);
}

TEST(SerialPath, DeviceThatVanishesIsReportedAndCanBeReopened) {
  const std::string link = linkPath("vanishing");
  auto pty = std::make_unique<PseudoTerminal>();
  ASSERT_TRUE(pty->open(link));
  SerialPort host;
  ASSERT_TRUE(host.open(link, 115200));
  const std::uint8_t hello[] = {1, 2, 3};
  pty->write(hello, 3);
  std::uint8_t buffer[16];
  long n = 0;
  for (int i = 0; i < 100 && n == 0; ++i) n = host.read(buffer, sizeof(buffer), 20);
  ASSERT_EQ(n, 3);

  pty->close();  // unplugged
  long result = 0;
  for (int i = 0; i < 100 && result == 0; ++i) result = host.read(buffer, sizeof(buffer), 20);
  EXPECT_EQ(result, -1);
  EXPECT_FALSE(host.isOpen());
  EXPECT_FALSE(host.lastError().empty());
  EXPECT_FALSE(host.write(hello, 3));
  EXPECT_FALSE(host.open(link, 115200));  // the symlink is gone with the device
  EXPECT_NE(host.lastError().find(link), std::string::npos);

  ASSERT_TRUE(pty->open(link));  // plugged in again
  ASSERT_TRUE(host.open(link, 115200)) << host.lastError();
  pty->write(hello, 3);
  n = 0;
  for (int i = 0; i < 100 && n == 0; ++i) n = host.read(buffer, sizeof(buffer), 20);
  EXPECT_EQ(n, 3);
  pty->close();
}

TEST(SerialPath, BadConfigurationIsReported) {
  SerialPort host;
  EXPECT_FALSE(host.open("/nonexistent/tty", 115200));
  EXPECT_NE(host.lastError().find("/nonexistent/tty"), std::string::npos);
  EXPECT_FALSE(host.open("/dev/null", 12345));
  EXPECT_NE(host.lastError().find("12345"), std::string::npos);
  std::uint8_t buffer[4];
  EXPECT_EQ(host.read(buffer, 4, 0), -1);
}
