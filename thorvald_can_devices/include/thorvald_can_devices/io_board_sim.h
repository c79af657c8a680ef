#pragma once

#include <cstdint>
#include <string>

#include "thorvald_base/robot_config.h"
#include "thorvald_can_devices/can_bus.h"
#include "thorvald_can_devices/cia401_protocol.h"

namespace thorvald_can_devices {

/// A simulated CiA 401 relay board: boots into pre-operational (boot-up heartbeat), follows NMT, drives its outputs
/// from RPDO1 while operational, echoes them with its inputs in TPDO1 on every change and every 100 ms, sends its
/// heartbeat every 100 ms, and drives the outputs to the error value (off) when RPDO1 stops for 0.5 s or the node
/// leaves operational. Faults: `silent` (neither sends nor hears: unpowered, outputs off), `stuck` (the relays keep
/// their state whatever is written: a welded contact, the echo shows it).
class IoBoardSim {
 public:
  explicit IoBoardSim(const thorvald_base::IoConfig& config);
  void handle(const CanFrame& f, CanBus& bus, double now_s);
  void step(double now_s, CanBus& bus);
  /// Returns false for an unknown fault.
  bool setFault(const std::string& fault, bool active);

  const std::string& name() const { return name_; }
  int node() const { return node_; }
  uint8_t outputs() const { return outputs_; }
  uint8_t nmtState() const { return state_; }
  uint8_t inputs = 0;  ///< what the board's digital inputs read (tests set it)

 private:
  void setOutputs(uint8_t value, CanBus& bus);
  void boot(double now_s, CanBus& bus);  ///< boot-up heartbeat, pre-operational

  std::string name_;
  int node_;
  uint8_t state_ = kHeartbeatPreOperational;
  uint8_t outputs_ = 0;
  bool booted_ = false, silent_ = false, stuck_ = false;
  double last_rpdo_s_ = -1e9, next_tpdo_s_ = 0.0, next_heartbeat_s_ = 0.0;
};

}  // namespace thorvald_can_devices
