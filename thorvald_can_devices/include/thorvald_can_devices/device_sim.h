#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "thorvald_base/robot_config.h"
#include "thorvald_can_devices/battery_sim.h"
#include "thorvald_can_devices/can_bus.h"
#include "thorvald_can_devices/cia402_axis_sim.h"
#include "thorvald_can_devices/io_board_sim.h"
#include "thorvald_can_devices/thorvald_drive_sim.h"

namespace thorvald_can_devices {
/// Every node of a robot file, simulated on one bus: the executable statement of the protocols (README).
class DeviceSim {
 public:
  explicit DeviceSim(const thorvald_base::RobotConfig& config);
  /// Frames one spinOnce() reads at most (the rest waits for the next one).
  static constexpr size_t kMaxFramesPerSpin = 1000;
  /// Reads the waiting frames from `bus` (at most kMaxFramesPerSpin) and answers them, then steps all devices to
  /// now_s.
  void spinOnce(double now_s, CanBus& bus);
  /// Injects (active) or removes a fault. `target`: driveN, batN, ioN or "bus"; faults: silent, stall, encoder
  /// (drives), alarm, silent (batteries), silent, stuck (relay boards), bus_off, error_passive (bus; removal sends the
  /// controller-restarted frame).
  /// Returns false with the reason for an unknown target or fault.
  bool inject(const std::string& target, const std::string& fault, bool active, CanBus& bus, std::string* message);
  const std::vector<ThorvaldDriveSim>& thorvaldDrives() const { return thorvald_; }
  const std::vector<Cia402AxisSim>& cia402Axes() const { return cia402_; }
  const std::vector<IoBoardSim>& ioBoards() const { return io_; }
  unsigned long framesHandled() const { return frames_handled_; }

 private:
  std::vector<ThorvaldDriveSim> thorvald_;
  std::vector<Cia402AxisSim> cia402_;
  std::vector<BatterySim> batteries_;
  std::vector<IoBoardSim> io_;
  std::map<int, std::vector<std::pair<int, size_t>>> drive_index_;  ///< drive -> (0 thorvald / 1 cia402, position)
  std::map<std::string, size_t> battery_index_;
  unsigned long frames_handled_ = 0;
};

}  // namespace thorvald_can_devices
