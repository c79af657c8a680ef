#include "cotton_harvester_sim/rover_device_emulator.h"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

namespace cotton_harvester {
namespace sim {

void makeParentDirectory(const std::string& path) {
  for (std::size_t i = path.find('/', 1); i != std::string::npos; i = path.find('/', i + 1))
    ::mkdir(path.substr(0, i).c_str(), 0755);
}

RoverDeviceEmulator::RoverDeviceEmulator(RoverSim& sim, const SerialBridgeParams& params,
                                         const std::string& manipulator_link, const std::string& navigation_link)
    : bridge_(sim, params) {
  makeParentDirectory(manipulator_link);
  makeParentDirectory(navigation_link);
  if (!manipulator_pty_.open(manipulator_link)) throw std::runtime_error(manipulator_pty_.lastError());
  if (!navigation_pty_.open(navigation_link)) throw std::runtime_error(navigation_pty_.lastError());
}

void RoverDeviceEmulator::serveLinks() {
  std::uint8_t buffer[512];
  long n;
  while ((n = manipulator_pty_.read(buffer, sizeof(buffer))) > 0) {
    const auto reply = bridge_.receiveManipulator(buffer, static_cast<std::size_t>(n));
    if (!reply.empty()) manipulator_pty_.write(reply.data(), reply.size());
  }
  while ((n = navigation_pty_.read(buffer, sizeof(buffer))) > 0)
    bridge_.receiveNavigation(buffer, static_cast<std::size_t>(n));
}

RoverSerialBridge::Output RoverDeviceEmulator::advance(double seconds, double timestep_s) {
  RoverSerialBridge::Output all;
  const int steps = std::max(1, static_cast<int>(std::lround(seconds / timestep_s)));
  for (int i = 0; i < steps; ++i) {
    auto out = bridge_.advance(timestep_s);
    all.manipulator.insert(all.manipulator.end(), out.manipulator.begin(), out.manipulator.end());
    all.navigation.insert(all.navigation.end(), out.navigation.begin(), out.navigation.end());
  }
  return all;
}

void RoverDeviceEmulator::send(const RoverSerialBridge::Output& frames, double lockstep_timeout_s,
                               const std::function<bool()>& keep_waiting) {
  if (!frames.manipulator.empty()) manipulator_pty_.write(frames.manipulator.data(), frames.manipulator.size());
  if (frames.navigation.empty()) return;
  const std::size_t commands = bridge_.driveCommands();
  navigation_pty_.write(frames.navigation.data(), frames.navigation.size());
  if (lockstep_timeout_s > 0.0) awaitDriveCommand(commands, lockstep_timeout_s, keep_waiting);
}

void RoverDeviceEmulator::awaitDriveCommand(std::size_t commands_before, double timeout_s,
                                            const std::function<bool()>& keep_waiting) {
  const auto deadline =
      std::chrono::steady_clock::now() +
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(timeout_s));
  while (bridge_.driveCommands() == commands_before && keep_waiting()) {
    if (std::chrono::steady_clock::now() >= deadline) {
      ++lockstep_timeouts_;
      return;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));
    serveLinks();
  }
}

}  // namespace sim
}  // namespace cotton_harvester
