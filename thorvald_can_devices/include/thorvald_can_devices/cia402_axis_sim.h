#pragma once

#include <string>

#include "thorvald_base/robot_config.h"
#include "thorvald_can_devices/can_bus.h"
#include "thorvald_can_devices/canopen_protocol.h"
#include "thorvald_can_devices/thorvald_drive_sim.h"

namespace thorvald_can_devices {
/// A simulated CiA 402 axis: object dictionary for the objects the base writes, NMT, the statusword state
/// machine driven by the controlword, profile velocity or profile position motion, TPDO1/TPDO2 on SYNC,
/// producer heartbeat (0x1017) and consumer heartbeat of the host (0x1016: fault with EMCY 0x8130 when lost).
class Cia402AxisSim {
 public:
  /// `steering`: position axis of a type-0 drive; otherwise its propulsion (velocity) axis.
  Cia402AxisSim(const thorvald_base::DriveConfig& drive, bool steering);
  int node() const { return node_; }
  void handle(const CanFrame& frame, CanBus& bus, double now_s);
  void step(double now_s, CanBus& bus);
  void setFault(const std::string& fault, bool active);
  Cia402State state() const { return state_; }
  double position() const { return position_; }  ///< [increments]
  double velocity() const { return velocity_; }  ///< [increments/s]
  int8_t mode() const { return mode_; }
  SimFaults faults() const { return faults_; }

 private:
  /// SYNC in operational: TPDO1 (statusword with set-point acknowledge and target reached, velocity) and TPDO2.
  void sendTpdos(CanBus& bus) const;
  /// Answers an SDO request: a write ack, a read reply or an abort (sends nothing for other transfer kinds).
  void answerSdo(const CanFrame& f, CanBus& bus);
  void writeObject(const SdoMessage& m, SdoMessage& reply);
  void readObject(const SdoMessage& m, SdoMessage& reply) const;
  /// RPDO1 in operational: the controlword drives the state machine; the target is a velocity or, on the
  /// rising edge of new set-point while enabled, a position.
  void applyRpdo1(const Cia402Rpdo1& p);
  void enterFault(uint16_t emcy, CanBus& bus);
  void reboot();
  thorvald_base::DriveConfig drive_;
  bool steering_;
  int node_;
  uint8_t nmt_ = kHeartbeatBootUp;
  bool boot_sent_ = false;
  Cia402State state_ = Cia402State::kSwitchOnDisabled;
  uint16_t controlword_ = 0;
  int8_t mode_ = 0;
  uint32_t heartbeat_ms_ = 0, consumer_ = 0, profile_velocity_ = 0, profile_acceleration_ = 0,
           profile_deceleration_ = 0;
  int32_t target_velocity_ = 0, target_position_ = 0;
  bool setpoint_ack_ = false;
  double position_ = 0.0, velocity_ = 0.0;
  double last_host_heartbeat_s_ = -1.0;
  SimFaults faults_;
  double now_s_ = -1.0, next_heartbeat_s_ = 0;
};

}  // namespace thorvald_can_devices
