#pragma once

#include <cstdint>
#include <optional>

#include "thorvald_can_devices/can_frame.h"

namespace thorvald_can_devices {

/// Frames of the Thorvald drive module (two-channel motor controller running the Thorvald script). Ids are a
/// base plus the node id. Byte layouts: README "Thorvald drive module". Decoders return nullopt for a frame of
/// the wrong id, length or message type: such frames are rejected, counted and never acted on.
namespace thorvald_ids {
constexpr uint32_t kCommand = 0x200;   ///< RPDO1 host -> drive
constexpr uint32_t kSetup = 0x300;     ///< RPDO2
constexpr uint32_t kMode = 0x400;      ///< RPDO3
constexpr uint32_t kSteering = 0x500;  ///< RPDO4
constexpr uint32_t kFeedback = 0x180;  ///< TPDO1 drive -> host
constexpr uint32_t kPower = 0x280;     ///< TPDO2
constexpr uint32_t kStatus = 0x380;    ///< TPDO3
constexpr uint32_t kInfo = 0x480;      ///< TPDO4
constexpr uint32_t kHeartbeat = 0x700;
}  // namespace thorvald_ids

/// Full-scale value of propulsion and steering commands.
constexpr int32_t kThorvaldFullScale = 1000;

/// RPDO1: sequence counter and propulsion command (channel 1), ±1000 full scale.
struct ThorvaldCommand {
  int32_t sequence = 0;
  int32_t propulsion = 0;
};
/// RPDO2: one setup value.
struct ThorvaldSetup {
  int32_t setup_id = 0;
  int32_t value = 0;
};
/// Setup ids the simulator and the host use.
namespace thorvald_setup {
constexpr int32_t kFaultReset = 1;        ///< value ignored: clears latched faults
constexpr int32_t kCommandTimeoutMs = 2;  ///< drive stops propulsion when no new sequence arrives for this long
constexpr int32_t kHeartbeatMs = 3;       ///< heartbeat period
}  // namespace thorvald_setup
enum class ThorvaldMode : int32_t { kDrive = 0, kHomeSteering = 1, kDecoupled = 2 };
/// RPDO4: type 0: steering max speed [steering motor rpm] and steering position (±1000 = ±str_lim);
/// type-1 pair: `position` carries the channel-2 propulsion command (±1000).
struct ThorvaldSteering {
  int32_t max_speed_rpm = 0;
  int32_t position = 0;
};
/// TPDO1: propulsion motor rpm, steering motor rpm (type-1 pair: channel-2 motor rpm), steering encoder count
/// (quadrature counts; type-1 pair: 0).
struct ThorvaldFeedback {
  int16_t propulsion_rpm = 0;
  int16_t steering_rpm = 0;
  int32_t steering_count = 0;
};
/// TPDO2: motor current [A x 10] and relative power [per mille of full output] per channel.
struct ThorvaldPower {
  int16_t current_da[2] = {0, 0};
  int16_t power_permille[2] = {0, 0};
};
/// Status flag bits of TPDO3 byte 0.
namespace thorvald_flags {
constexpr uint8_t kPropulsionEncoderFault = 0x80;
constexpr uint8_t kSteeringEncoderFault = 0x40;
constexpr uint8_t kAlignmentFault = 0x20;
constexpr uint8_t kPowerStageOff = 0x10;
constexpr uint8_t kStall = 0x08;
constexpr uint8_t kHomingExceeded = 0x04;
constexpr uint8_t kIllegalCommand = 0x02;
constexpr uint8_t kControllerOk = 0x01;
constexpr uint8_t kFaultMask = 0xFE;
}  // namespace thorvald_flags
/// TPDO3: status flags, max temperature [degC], battery current [A x 10], battery voltage [V x 10].
struct ThorvaldStatus {
  uint8_t flags = 0;
  int8_t max_temperature_c = 0;
  int16_t battery_current_da = 0;
  uint16_t battery_voltage_dv = 0;
};
/// TPDO4, byte 3 = message type.
struct ThorvaldInfo {
  uint8_t type = 0;             ///< 1 homing, 2 type check + script version, 3 encoder ppr
  int8_t home_direction = 0;    ///< type 1: -1 / +1 while homing, 0 when homing is finished
  int16_t home_speed_rpm = 0;   ///< type 1: steering motor rpm used for homing
  int32_t home_count = 0;       ///< type 1: encoder counts travelled while homing
  uint8_t controller_type = 0;  ///< type 2: 0 propulsion + steering, 1 propulsion pair
  uint16_t script_version = 0;  ///< type 2
  int32_t encoder_ppr = 0;      ///< type 3: steering encoder pulses per revolution
};
constexpr uint8_t kHeartbeatBootUp = 0x00, kHeartbeatStopped = 0x04, kHeartbeatOperational = 0x05,
                  kHeartbeatPreOperational = 0x7F;

CanFrame encodeCommand(int node, const ThorvaldCommand& c);
CanFrame encodeSetup(int node, const ThorvaldSetup& s);
CanFrame encodeMode(int node, ThorvaldMode m);
CanFrame encodeSteering(int node, const ThorvaldSteering& s);
CanFrame encodeFeedback(int node, const ThorvaldFeedback& f);
CanFrame encodePower(int node, const ThorvaldPower& p);
CanFrame encodeStatus(int node, const ThorvaldStatus& s);
CanFrame encodeInfo(int node, const ThorvaldInfo& i);
CanFrame encodeHeartbeat(int node, uint8_t state);

std::optional<ThorvaldCommand> decodeCommand(const CanFrame& f);
std::optional<ThorvaldSetup> decodeSetup(const CanFrame& f);
std::optional<ThorvaldMode> decodeMode(const CanFrame& f);
std::optional<ThorvaldSteering> decodeSteering(const CanFrame& f);
std::optional<ThorvaldFeedback> decodeFeedback(const CanFrame& f);
std::optional<ThorvaldPower> decodePower(const CanFrame& f);
std::optional<ThorvaldStatus> decodeStatus(const CanFrame& f);
std::optional<ThorvaldInfo> decodeInfo(const CanFrame& f);
std::optional<uint8_t> decodeHeartbeat(const CanFrame& f);

/// Node id of a frame whose id is `base` + node (1..127), or -1.
int nodeOf(const CanFrame& f, uint32_t base);

/// Words for the set fault bits of a status byte ("stall, illegal command"); "controller not ok" when bit 0 is
/// clear; "" when all is well.
std::string describeFlags(uint8_t flags);

}  // namespace thorvald_can_devices
