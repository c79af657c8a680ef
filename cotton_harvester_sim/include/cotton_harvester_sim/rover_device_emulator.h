#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "cotton_harvester/control/serial_port.h"
#include "cotton_harvester_sim/rover_serial_bridge.h"
#include "cotton_harvester_sim/rover_sim.h"

namespace cotton_harvester {
namespace sim {

/// The simulated rover's two serial controllers as devices: the manipulation and navigation controllers
/// (RoverSerialBridge) answer on pseudo-terminals whose symlinks the stack's `manipulator` and `rover` nodes open as
/// serial ports. Advancing it advances the simulation. ROS-free; not thread-safe.
class RoverDeviceEmulator {
 public:
  /// Creates the folders of the two links and the pseudo-terminals behind them. Throws std::runtime_error when a
  /// link cannot be made, std::invalid_argument on bad bridge parameters.
  RoverDeviceEmulator(RoverSim& sim, const SerialBridgeParams& params, const std::string& manipulator_link,
                      const std::string& navigation_link);

  /// Reads what the host wrote on both links; answers the manipulation controller's queries.
  void serveLinks();

  /// Advances the simulation by `seconds` in steps of timestep_s [s] (at least one step) and returns the frames due.
  RoverSerialBridge::Output advance(double seconds, double timestep_s);

  /// Writes the frames to the host. After navigation telemetry, when lockstep_timeout_s > 0 [s of wall time], keeps
  /// serving the links until the host answered with a drive command, the timeout (counted) or !keep_waiting().
  void send(const RoverSerialBridge::Output& frames, double lockstep_timeout_s,
            const std::function<bool()>& keep_waiting);

  int lockstepTimeouts() const { return lockstep_timeouts_; }
  std::size_t rejectedBytes() const { return bridge_.rejectedBytes(); }
  const RoverSerialBridge& bridge() const { return bridge_; }

 private:
  void awaitDriveCommand(std::size_t commands_before, double timeout_s, const std::function<bool()>& keep_waiting);

  RoverSerialBridge bridge_;
  control::PseudoTerminal manipulator_pty_, navigation_pty_;
  int lockstep_timeouts_ = 0;
};

/// mkdir -p of the folder that holds `path`.
void makeParentDirectory(const std::string& path);

}  // namespace sim
}  // namespace cotton_harvester
