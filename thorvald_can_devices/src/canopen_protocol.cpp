#include "thorvald_can_devices/canopen_protocol.h"

#include "thorvald_can_devices/thorvald_drive_protocol.h"

namespace thorvald_can_devices {

CanFrame encodeNmt(NmtCommand command, int node) {
  return makeFrame(canopen_ids::kNmt, {static_cast<uint8_t>(command), static_cast<uint8_t>(node)});
}
std::optional<NmtMessage> decodeNmt(const CanFrame& f) {
  if (f.isError() || f.isExtended() || f.isRemote() || f.stdId() != canopen_ids::kNmt || f.length != 2)
    return std::nullopt;
  const uint8_t c = f.data[0];
  if (c != 0x01 && c != 0x02 && c != 0x80 && c != 0x81 && c != 0x82) return std::nullopt;
  if (f.data[1] > 127) return std::nullopt;
  return NmtMessage{static_cast<NmtCommand>(c), f.data[1]};
}
CanFrame encodeSync() { return makeFrame(canopen_ids::kSync, {}); }

CanFrame encodeEmergency(int node, const Emergency& e) {
  CanFrame f;
  f.id = canopen_ids::kEmcy + static_cast<uint32_t>(node);
  f.length = 8;
  putU16(f, 0, e.error_code);
  f.data[2] = e.error_register;
  return f;
}
std::optional<Emergency> decodeEmergency(const CanFrame& f) {
  if (nodeOf(f, canopen_ids::kEmcy) < 0 || f.length != 8) return std::nullopt;
  return Emergency{getU16(f, 0), f.data[2]};
}

namespace {
CanFrame encodeSdo(uint32_t base, int node, const SdoMessage& m) {
  CanFrame f;
  f.id = base + static_cast<uint32_t>(node);
  f.length = 8;
  const uint8_t size = (m.size >= 1 && m.size <= 4) ? m.size : 4;
  switch (m.kind) {
    case SdoMessage::Kind::kWriteRequest:
      f.data[0] = static_cast<uint8_t>(0x23 | ((4 - size) << 2));
      break;
    case SdoMessage::Kind::kReadReply:
      f.data[0] = static_cast<uint8_t>(0x43 | ((4 - size) << 2));
      break;
    case SdoMessage::Kind::kWriteAck:
      f.data[0] = 0x60;
      break;
    case SdoMessage::Kind::kReadRequest:
      f.data[0] = 0x40;
      break;
    case SdoMessage::Kind::kAbort:
      f.data[0] = 0x80;
      break;
  }
  putU16(f, 1, m.index);
  f.data[3] = m.subindex;
  if (m.kind == SdoMessage::Kind::kWriteRequest || m.kind == SdoMessage::Kind::kReadReply) {
    for (int i = 0; i < size; ++i) f.data[4 + i] = static_cast<uint8_t>((m.value >> (8 * i)) & 0xFF);
  } else if (m.kind == SdoMessage::Kind::kAbort) {
    putU32(f, 4, m.value);
  }
  return f;
}
}  // namespace

CanFrame encodeSdoRequest(int node, const SdoMessage& m) { return encodeSdo(canopen_ids::kSdoRequest, node, m); }
CanFrame encodeSdoReply(int node, const SdoMessage& m) { return encodeSdo(canopen_ids::kSdoReply, node, m); }

std::optional<SdoMessage> decodeSdo(const CanFrame& f) {
  const bool request = nodeOf(f, canopen_ids::kSdoRequest) > 0;
  const bool reply = nodeOf(f, canopen_ids::kSdoReply) > 0;
  if ((!request && !reply) || f.length != 8) return std::nullopt;
  SdoMessage m;
  const uint8_t cmd = f.data[0];
  m.index = getU16(f, 1);
  m.subindex = f.data[3];
  const auto expedited = [&](SdoMessage::Kind kind) -> std::optional<SdoMessage> {
    if ((cmd & 0x03) != 0x03) return std::nullopt;  // must be expedited with size indicated
    m.kind = kind;
    m.size = static_cast<uint8_t>(4 - ((cmd >> 2) & 0x03));
    m.value = 0;
    for (int i = 0; i < m.size; ++i) m.value |= static_cast<uint32_t>(f.data[4 + i]) << (8 * i);
    return m;
  };
  if (request) {
    if ((cmd & 0xF0) == 0x20) return expedited(SdoMessage::Kind::kWriteRequest);
    if (cmd == 0x40) {
      m.kind = SdoMessage::Kind::kReadRequest;
      return m;
    }
  } else {
    if ((cmd & 0xF0) == 0x40) return expedited(SdoMessage::Kind::kReadReply);
    if (cmd == 0x60) {
      m.kind = SdoMessage::Kind::kWriteAck;
      return m;
    }
  }
  if (cmd == 0x80) {
    m.kind = SdoMessage::Kind::kAbort;
    m.value = getU32(f, 4);
    return m;
  }
  return std::nullopt;
}

Cia402State stateOf(uint16_t sw) {
  if ((sw & 0x4F) == 0x00) return Cia402State::kNotReadyToSwitchOn;
  if ((sw & 0x4F) == 0x40) return Cia402State::kSwitchOnDisabled;
  if ((sw & 0x6F) == 0x21) return Cia402State::kReadyToSwitchOn;
  if ((sw & 0x6F) == 0x23) return Cia402State::kSwitchedOn;
  if ((sw & 0x6F) == 0x27) return Cia402State::kOperationEnabled;
  if ((sw & 0x6F) == 0x07) return Cia402State::kQuickStopActive;
  if ((sw & 0x4F) == 0x0F) return Cia402State::kFaultReactionActive;
  if ((sw & 0x4F) == 0x08) return Cia402State::kFault;
  return Cia402State::kUnknown;
}

const char* toString(Cia402State s) {
  switch (s) {
    case Cia402State::kNotReadyToSwitchOn:
      return "not ready to switch on";
    case Cia402State::kSwitchOnDisabled:
      return "switch on disabled";
    case Cia402State::kReadyToSwitchOn:
      return "ready to switch on";
    case Cia402State::kSwitchedOn:
      return "switched on";
    case Cia402State::kOperationEnabled:
      return "operation enabled";
    case Cia402State::kQuickStopActive:
      return "quick stop active";
    case Cia402State::kFaultReactionActive:
      return "fault reaction active";
    case Cia402State::kFault:
      return "fault";
    case Cia402State::kUnknown:
      break;
  }
  return "unknown";
}

uint16_t statuswordOf(Cia402State s) {
  switch (s) {
    case Cia402State::kNotReadyToSwitchOn:
      return 0x0000;
    case Cia402State::kSwitchOnDisabled:
      return 0x0040;
    case Cia402State::kReadyToSwitchOn:
      return 0x0021;
    case Cia402State::kSwitchedOn:
      return 0x0023;
    case Cia402State::kOperationEnabled:
      return 0x0027;
    case Cia402State::kQuickStopActive:
      return 0x0007;
    case Cia402State::kFaultReactionActive:
      return 0x000F;
    case Cia402State::kFault:
      return 0x0008;
    case Cia402State::kUnknown:
      break;
  }
  return 0x0000;
}

uint16_t controlwordTowardsOperation(Cia402State s) {
  switch (s) {
    case Cia402State::kSwitchOnDisabled:
      return cia402::kCwShutdown;
    case Cia402State::kReadyToSwitchOn:
      return cia402::kCwSwitchOn;
    case Cia402State::kSwitchedOn:
    case Cia402State::kOperationEnabled:
      return cia402::kCwEnableOperation;
    case Cia402State::kQuickStopActive:
      return 0x0000;  // disable voltage: back to switch on disabled
    default:
      return 0x0000;
  }
}

Cia402State nextState(Cia402State s, uint16_t cw) {
  const bool disable_voltage = (cw & 0x02) == 0;
  const bool quick_stop = (cw & 0x06) == 0x02;
  const bool shutdown = (cw & 0x87) == 0x06;
  const bool switch_on = (cw & 0x8F) == 0x07;
  const bool enable = (cw & 0x8F) == 0x0F;
  switch (s) {
    case Cia402State::kSwitchOnDisabled:
      return shutdown ? Cia402State::kReadyToSwitchOn : s;
    case Cia402State::kReadyToSwitchOn:
      if (switch_on) return Cia402State::kSwitchedOn;
      if (enable) return Cia402State::kOperationEnabled;
      if (disable_voltage || quick_stop) return Cia402State::kSwitchOnDisabled;
      return s;
    case Cia402State::kSwitchedOn:
      if (enable) return Cia402State::kOperationEnabled;
      if (shutdown) return Cia402State::kReadyToSwitchOn;
      if (disable_voltage || quick_stop) return Cia402State::kSwitchOnDisabled;
      return s;
    case Cia402State::kOperationEnabled:
      if (quick_stop) return Cia402State::kQuickStopActive;
      if (switch_on) return Cia402State::kSwitchedOn;
      if (shutdown) return Cia402State::kReadyToSwitchOn;
      if (disable_voltage) return Cia402State::kSwitchOnDisabled;
      return s;
    case Cia402State::kQuickStopActive:
      if (disable_voltage) return Cia402State::kSwitchOnDisabled;
      if (enable) return Cia402State::kOperationEnabled;
      return s;
    default:
      return s;
  }
}

CanFrame encodeRpdo1(int node, const Cia402Rpdo1& p) {
  CanFrame f;
  f.id = canopen_ids::kRpdo1 + static_cast<uint32_t>(node);
  f.length = 6;
  putU16(f, 0, p.controlword);
  putI32(f, 2, p.target);
  return f;
}
CanFrame encodeTpdo1(int node, const Cia402Tpdo1& p) {
  CanFrame f;
  f.id = canopen_ids::kTpdo1 + static_cast<uint32_t>(node);
  f.length = 6;
  putU16(f, 0, p.statusword);
  putI32(f, 2, p.actual_velocity);
  return f;
}
CanFrame encodeTpdo2(int node, const Cia402Tpdo2& p) {
  CanFrame f;
  f.id = canopen_ids::kTpdo2 + static_cast<uint32_t>(node);
  f.length = 5;
  putI32(f, 0, p.actual_position);
  f.data[4] = static_cast<uint8_t>(p.mode_display);
  return f;
}
std::optional<Cia402Rpdo1> decodeRpdo1(const CanFrame& f) {
  if (nodeOf(f, canopen_ids::kRpdo1) < 0 || f.length != 6) return std::nullopt;
  return Cia402Rpdo1{getU16(f, 0), getI32(f, 2)};
}
std::optional<Cia402Tpdo1> decodeTpdo1(const CanFrame& f) {
  if (nodeOf(f, canopen_ids::kTpdo1) < 0 || f.length != 6) return std::nullopt;
  return Cia402Tpdo1{getU16(f, 0), getI32(f, 2)};
}
std::optional<Cia402Tpdo2> decodeTpdo2(const CanFrame& f) {
  if (nodeOf(f, canopen_ids::kTpdo2) < 0 || f.length != 5) return std::nullopt;
  return Cia402Tpdo2{getI32(f, 0), static_cast<int8_t>(f.data[4])};
}

std::optional<uint8_t> nmtStateAfter(NmtCommand command) {
  switch (command) {
    case NmtCommand::kStart:
      return kHeartbeatOperational;
    case NmtCommand::kStop:
      return kHeartbeatStopped;
    case NmtCommand::kPreOperational:
      return kHeartbeatPreOperational;
    default:
      return std::nullopt;
  }
}

}  // namespace thorvald_can_devices
