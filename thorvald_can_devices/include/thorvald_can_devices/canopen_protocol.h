#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "thorvald_can_devices/can_frame.h"

namespace thorvald_can_devices {

/// CANopen CiA 301 services and the CiA 402 drive profile, as far as the base uses them. Layouts: README.
namespace canopen_ids {
constexpr uint32_t kNmt = 0x000, kSync = 0x080, kEmcy = 0x080, kTpdo1 = 0x180, kTpdo2 = 0x280, kRpdo1 = 0x200,
                   kSdoReply = 0x580, kSdoRequest = 0x600, kHeartbeat = 0x700;
}  // namespace canopen_ids

enum class NmtCommand : uint8_t {
  kStart = 0x01,
  kStop = 0x02,
  kPreOperational = 0x80,
  kResetNode = 0x81,
  kResetCommunication = 0x82
};
/// NMT frame [command, node]; node 0 addresses every node.
CanFrame encodeNmt(NmtCommand command, int node);
struct NmtMessage {
  NmtCommand command;
  int node;
};
std::optional<NmtMessage> decodeNmt(const CanFrame& f);
/// The heartbeat state (CiA 301: 0x05 operational, 0x04 stopped, 0x7F pre-operational) a node enters on an NMT
/// command; nullopt for the two resets, after which the node boots again.
std::optional<uint8_t> nmtStateAfter(NmtCommand command);
CanFrame encodeSync();

/// Emergency message: error code (0 = error reset), error register, 5 manufacturer bytes (zero here).
struct Emergency {
  uint16_t error_code = 0;
  uint8_t error_register = 0;
};
CanFrame encodeEmergency(int node, const Emergency& e);
std::optional<Emergency> decodeEmergency(const CanFrame& f);

/// One expedited SDO exchange.
struct SdoMessage {
  enum class Kind { kWriteRequest, kWriteAck, kReadRequest, kReadReply, kAbort } kind = Kind::kWriteRequest;
  uint16_t index = 0;
  uint8_t subindex = 0;
  uint32_t value = 0;  ///< data of a write request or read reply; abort code of an abort
  uint8_t size = 0;    ///< bytes of `value` (1..4) for write requests and read replies
};
CanFrame encodeSdoRequest(int node, const SdoMessage& m);  ///< 0x600 + node
CanFrame encodeSdoReply(int node, const SdoMessage& m);    ///< 0x580 + node
/// Decodes a request (0x600 + node) or a reply (0x580 + node); segmented transfers are rejected.
std::optional<SdoMessage> decodeSdo(const CanFrame& f);

/// CiA 402 objects used by the base.
namespace cia402 {
constexpr uint16_t kControlword = 0x6040, kStatusword = 0x6041, kModes = 0x6060, kModesDisplay = 0x6061,
                   kActualPosition = 0x6064, kActualVelocity = 0x606C, kTargetPosition = 0x607A,
                   kProfileVelocity = 0x6081, kProfileAcceleration = 0x6083, kProfileDeceleration = 0x6084,
                   kTargetVelocity = 0x60FF, kProducerHeartbeat = 0x1017, kConsumerHeartbeat = 0x1016;
constexpr int8_t kModeProfilePosition = 1, kModeProfileVelocity = 3, kModeHoming = 6;
constexpr uint16_t kCwShutdown = 0x06, kCwSwitchOn = 0x07, kCwEnableOperation = 0x0F, kCwQuickStop = 0x02,
                   kCwFaultReset = 0x80, kCwNewSetPoint = 0x10, kCwChangeImmediately = 0x20;
constexpr uint16_t kSwSetPointAck = 0x1000, kSwTargetReached = 0x0400;
}  // namespace cia402

enum class Cia402State {
  kNotReadyToSwitchOn,
  kSwitchOnDisabled,
  kReadyToSwitchOn,
  kSwitchedOn,
  kOperationEnabled,
  kQuickStopActive,
  kFaultReactionActive,
  kFault,
  kUnknown
};
Cia402State stateOf(uint16_t statusword);
const char* toString(Cia402State s);
/// Statusword bits that encode `s` (what a drive in that state reports).
uint16_t statuswordOf(Cia402State s);
/// The controlword that moves a drive in state `s` one step towards operation enabled (fault: none, 0).
uint16_t controlwordTowardsOperation(Cia402State s);
/// The state a drive in `s` enters on `controlword` (device side of the state machine; fault reset is an edge and
/// handled by the caller).
Cia402State nextState(Cia402State s, uint16_t controlword);

/// Fixed PDO mapping of the CiA 402 drives (README): RPDO1 = controlword u16 + target i32 (target velocity in
/// velocity mode, target position in position mode); TPDO1 = statusword u16 + actual velocity i32;
/// TPDO2 = actual position i32 + modes of operation display i8.
struct Cia402Rpdo1 {
  uint16_t controlword = 0;
  int32_t target = 0;
};
struct Cia402Tpdo1 {
  uint16_t statusword = 0;
  int32_t actual_velocity = 0;  ///< [encoder increments/s]
};
struct Cia402Tpdo2 {
  int32_t actual_position = 0;  ///< [encoder increments]
  int8_t mode_display = 0;
};
CanFrame encodeRpdo1(int node, const Cia402Rpdo1& p);
CanFrame encodeTpdo1(int node, const Cia402Tpdo1& p);
CanFrame encodeTpdo2(int node, const Cia402Tpdo2& p);
std::optional<Cia402Rpdo1> decodeRpdo1(const CanFrame& f);
std::optional<Cia402Tpdo1> decodeTpdo1(const CanFrame& f);
std::optional<Cia402Tpdo2> decodeTpdo2(const CanFrame& f);

}  // namespace thorvald_can_devices
