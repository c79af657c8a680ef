#pragma once
// An in-process test rig: CanBaseHardware and DeviceSim on one virtual bus, both stepped by the test on a fake
// clock (2 ms simulator steps, 20 ms host cycles), plus a spy endpoint that sees every frame.
#include <unistd.h>

#include <memory>
#include <string>
#include <vector>

#include "thorvald_base/robot_config.h"
#include "thorvald_can_devices/can_base_hardware.h"
#include "thorvald_can_devices/device_sim.h"
#include "thorvald_can_devices/virtual_can_bus.h"

namespace thorvald_can_devices {

class Rig {
 public:
  explicit Rig(const std::string& robot_file, bool with_sim = true)
      : config(thorvald_base::loadRobotConfigFile(robot_file)),
        bus_name("rig" + std::to_string(::getpid()) + "_" + std::to_string(counter()++)),
        sim_bus(std::make_unique<VirtualCanBus>(bus_name)),
        spy(std::make_unique<VirtualCanBus>(bus_name)),
        sim(config),
        hw(CanBaseOptions{0.0, "", 1000}, [this] { return t; }) {
    with_sim_ = with_sim;
    hw.initializeOnBus(config, std::make_unique<VirtualCanBus>(bus_name));
    drives = hw.takeDrives();
    batteries = hw.takeBatteries();
    io_boards = hw.takeIoBoards();
    commands.resize(drives.size());
  }

  /// One 20 ms host cycle: simulator steps, host poll, drive commands and updates.
  void cycle(bool host = true) {
    for (int k = 0; k < 10; ++k) {
      t += 0.002;
      if (with_sim_) sim.spinOnce(t, *sim_bus);
    }
    drainSpy();
    if (!host) return;
    hw.poll(t);
    for (size_t i = 0; i < drives.size(); ++i) {
      drives[i]->setCommand(commands[i]);
      drives[i]->update(t);
    }
  }
  void run(double seconds, bool host = true) {
    const int n = static_cast<int>(seconds / 0.02 + 0.5);
    for (int i = 0; i < n; ++i) cycle(host);
  }
  /// Every frame the spy saw since the last call.
  std::vector<CanFrame> spied() {
    drainSpy();
    std::vector<CanFrame> out;
    out.swap(spied_);
    return out;
  }
  void drainSpy() {
    CanFrame f;
    while (spy->receive(&f)) spied_.push_back(f);
  }
  bool inject(const std::string& target, const std::string& fault, bool active) {
    std::string msg;
    return sim.inject(target, fault, active, *sim_bus, &msg);
  }

  double t = 1000.0;
  thorvald_base::RobotConfig config;
  std::string bus_name;
  std::unique_ptr<VirtualCanBus> sim_bus, spy;
  DeviceSim sim;
  CanBaseHardware hw;
  std::vector<std::unique_ptr<thorvald_base::MotorDrive>> drives;
  std::vector<std::unique_ptr<thorvald_base::Battery>> batteries;
  std::vector<std::unique_ptr<thorvald_base::IoBoard>> io_boards;
  std::vector<thorvald_base::DriveCommand> commands;

 private:
  static int& counter() {
    static int n = 0;
    return n;
  }
  bool with_sim_ = true;
  std::vector<CanFrame> spied_;
};

}  // namespace thorvald_can_devices
