#pragma once

#include <string>
#include <vector>

#include "thorvald_base/robot_config.h"
#include "thorvald_can_devices/can_bus.h"
#include "thorvald_can_devices/thorvald_drive_protocol.h"

namespace thorvald_can_devices {

/// Faults a simulated node can be given at run time.
struct SimFaults {
  bool silent = false;   ///< sends nothing, hears nothing; on recovery it reboots (boot-up heartbeat)
  bool stall = false;    ///< propulsion blocked: speed 0, stall flag (Thorvald) / drive fault (CiA 402)
  bool encoder = false;  ///< propulsion encoder fault
};

/// A simulated Thorvald drive controller (one node, one or two channels) answering as the hardware does:
/// boots pre-operational, starts on NMT start, follows propulsion and steering commands with the robot file's
/// acceleration and steering rate, stops propulsion when commands stop coming (setup 2, default 500 ms), homes
/// steering in mode 1, and sends TPDO1-3 every `tpdo_period_s`, TPDO4 info every second, heartbeat every 100 ms.
class ThorvaldDriveSim {
 public:
  explicit ThorvaldDriveSim(std::vector<thorvald_base::DriveConfig> channels);
  int node() const { return node_; }
  /// Handles one frame from the bus (ignores frames not for this node).
  void handle(const CanFrame& frame, CanBus& bus);
  /// Advances to now_s and sends what is due.
  void step(double now_s, CanBus& bus);
  void setFault(const std::string& fault, bool active);
  SimFaults faults() const { return faults_; }
  /// Ground truth: wheel speed [rad/s] and steering angle [rad] of channel c.
  double wheelSpeed(size_t c) const { return wheel_radps_[c]; }
  double steering() const { return steering_rad_; }
  int32_t lastSequence() const { return last_sequence_; }
  unsigned long commandsReceived() const { return commands_received_; }
  unsigned long rejected() const { return rejected_; }
  double tpdo_period_s = 0.02;
  double heartbeat_period_s = 0.1;

 private:
  /// Wheel speeds follow the command at the robot file's acceleration while driving (operational, fresh
  /// command, no latched fault, not homing); they coast to zero otherwise, and stay at zero when stalled.
  void stepPropulsion(double now_s, double dt, bool running, bool blocked);
  /// Steering (type 0) follows its command at the limited rate, or travels home at half rate in mode 1.
  void stepSteering(double dt, bool running, bool blocked);
  /// TPDO1-3 (feedback, power, status) and, while homing or until its end is reported, homing info.
  void sendTpdos(CanBus& bus);
  /// TPDO4 info, alternating kinds 2 and 3.
  void sendInfo(CanBus& bus);
  void reboot();
  std::vector<thorvald_base::DriveConfig> channels_;
  int node_, type_;
  uint8_t nmt_ = kHeartbeatBootUp;
  bool boot_sent_ = false;
  ThorvaldMode mode_ = ThorvaldMode::kDrive;
  int32_t command_[2] = {0, 0};
  int32_t steering_command_ = 0;
  int32_t steering_max_rpm_ = 0;
  int32_t last_sequence_ = 0;
  double last_command_s_ = -1e9;
  double command_timeout_s_ = 0.5;
  double wheel_radps_[2] = {0, 0};
  double steering_rad_ = 0.0, steering_radps_ = 0.0;
  double home_travel_rad_ = 0.0;
  bool homing_reported_done_ = true;
  uint8_t latched_flags_ = 0;
  SimFaults faults_;
  double now_s_ = -1.0, next_tpdo_s_ = 0, next_heartbeat_s_ = 0, next_info_s_ = 0;
  int info_kind_ = 2;
  unsigned long commands_received_ = 0, rejected_ = 0;
};

}  // namespace thorvald_can_devices
