#pragma once

#include <memory>
#include <string>
#include <vector>

#include "thorvald_base/motor_drive.h"
#include "thorvald_can_devices/can_device.h"
#include "thorvald_can_devices/canopen_protocol.h"

namespace thorvald_can_devices {

/// Node id of the host on a CiA 402 bus: its heartbeat is 0x700 + 127, the drives consume it.
constexpr int kHostNode = 127;
/// Host heartbeat period and the time the drives are told to wait for it [s].
constexpr double kHostHeartbeatPeriodS = 0.1;
constexpr int kHostHeartbeatTimeoutMs = 500;
/// Node id offset of the steering axis of a type-0 drive that speaks CiA 402 (propulsion axis at `node`).
constexpr int kCia402SteeringNodeOffset = 64;

/// Host side of one CiA 402 axis: SDO configuration (heartbeats, mode of operation, profile values), NMT start,
/// the statusword state machine up to operation enabled, fault reset, PDO targets and actuals, EMCY.
/// Velocity axes run profile velocity (mode 3), position axes profile position (mode 1) with the new-set-point
/// handshake (controlword bit 4, statusword bit 12).
class Cia402Axis : public CanDevice {
 public:
  enum class Kind { kVelocity, kPosition };
  struct Setup {
    std::string name;  ///< "drive2 propulsion"
    int node = 1;
    Kind kind = Kind::kVelocity;
    uint32_t profile_velocity = 0;      ///< [increments/s] (position axes)
    uint32_t profile_acceleration = 0;  ///< [increments/s^2]
  };
  Cia402Axis(CanBus* bus, Setup setup);

  std::string label() const override { return setup_.name + " (cia402 node " + std::to_string(setup_.node) + ")"; }
  std::vector<uint32_t> receiveIds() const override;
  std::vector<uint32_t> transmitIds() const override;
  void start(double now_s) override;
  void handle(const CanFrame& frame, double now_s) override;
  void tick(double now_s) override;
  bool operational() const override;
  unsigned long malformed() const override { return malformed_; }

  /// Target velocity [increments/s] or position [increments], sent in RPDO1 by sendTarget().
  void setTarget(int32_t target) { target_ = target; }
  void sendTarget();
  int32_t actualVelocity() const { return actual_velocity_; }
  int32_t actualPosition() const { return actual_position_; }
  bool hasFeedback() const { return feedback_seen_; }
  Cia402State state() const { return state_; }
  bool online() const;
  /// Fault text ("" when none).
  std::string fault() const;
  std::string describe() const;
  void clearFault() { fault_reset_pending_ = true; }
  /// The host sent a SYNC: the axis owes a TPDO1 answer.
  void syncSent() { ++syncs_unanswered_; }
  /// Running, but its TPDOs stopped: more than 3 SYNCs unanswered and none for the feedback timeout.
  bool feedbackSilent() const;
  void setFeedbackTimeout(double timeout_s) { feedback_timeout_s_ = timeout_s; }

 private:
  enum class Phase { kConfiguring, kStarting, kRunning, kFailed };
  void sendNextSdo(double now_s);

  CanBus* bus_;
  Setup setup_;
  std::vector<SdoMessage> sdo_writes_;
  size_t sdo_next_ = 0;
  int sdo_attempts_ = 0;
  double sdo_sent_s_ = -1e9;
  Phase phase_ = Phase::kConfiguring;
  std::string failure_;
  double now_s_ = 0.0;
  double last_heartbeat_s_ = -1e9;
  bool heard_ = false;
  uint8_t nmt_state_ = 0;
  Cia402State state_ = Cia402State::kUnknown;
  uint16_t statusword_ = 0;
  int32_t actual_velocity_ = 0, actual_position_ = 0;
  bool feedback_seen_ = false;
  double last_tpdo_s_ = -1e9;
  int syncs_unanswered_ = 0;
  double feedback_timeout_s_ = 0.06;
  int32_t target_ = 0, sent_target_ = 0;
  bool setpoint_pending_ = false;
  bool fault_reset_pending_ = false;
  int fault_reset_step_ = 0;
  uint16_t emcy_code_ = 0;
  unsigned long malformed_ = 0;
};

/// A drive of the robot file on CiA 402 controllers: the propulsion axis at `node`, and for a type-0 drive the
/// steering axis at `node + 64`.
class Cia402Drive : public thorvald_base::MotorDrive {
 public:
  Cia402Drive(const thorvald_base::DriveConfig& config, std::shared_ptr<Cia402Axis> propulsion,
              std::shared_ptr<Cia402Axis> steering);
  /// The axis setups a drive entry needs (1 or 2).
  static std::vector<Cia402Axis::Setup> axesFor(const thorvald_base::DriveConfig& config);

  void setCommand(const thorvald_base::DriveCommand& command) override { command_ = command; }
  void update(double now_s) override;
  thorvald_base::DriveFeedback feedback() const override;
  thorvald_base::DriveStatus status() const override;
  void reconfigure(const thorvald_base::DriveConfig& config) override { config_ = config; }
  void clearFault() override;

 private:
  thorvald_base::DriveConfig config_;
  std::shared_ptr<Cia402Axis> propulsion_, steering_;
  thorvald_base::DriveCommand command_;
  double wheel_position_rad_ = 0.0;
  double last_update_s_ = -1.0;
};

}  // namespace thorvald_can_devices
