#include "thorvald_can_devices/thorvald_drive_protocol.h"

namespace thorvald_can_devices {
namespace {
CanFrame frame(uint32_t base, int node, uint8_t length) {
  CanFrame f;
  f.id = base + static_cast<uint32_t>(node);
  f.length = length;
  return f;
}
bool is(const CanFrame& f, uint32_t base, uint8_t length) { return nodeOf(f, base) > 0 && f.length == length; }
}  // namespace

int nodeOf(const CanFrame& f, uint32_t base) {
  if (f.isError() || f.isExtended() || f.isRemote()) return -1;
  const uint32_t id = f.stdId();
  if (id <= base || id > base + 127) return -1;
  return static_cast<int>(id - base);
}

CanFrame encodeCommand(int node, const ThorvaldCommand& c) {
  CanFrame f = frame(thorvald_ids::kCommand, node, 8);
  putI32(f, 0, c.sequence);
  putI32(f, 4, c.propulsion);
  return f;
}
CanFrame encodeSetup(int node, const ThorvaldSetup& s) {
  CanFrame f = frame(thorvald_ids::kSetup, node, 8);
  putI32(f, 0, s.setup_id);
  putI32(f, 4, s.value);
  return f;
}
CanFrame encodeMode(int node, ThorvaldMode m) {
  CanFrame f = frame(thorvald_ids::kMode, node, 4);
  putI32(f, 0, static_cast<int32_t>(m));
  return f;
}
CanFrame encodeSteering(int node, const ThorvaldSteering& s) {
  CanFrame f = frame(thorvald_ids::kSteering, node, 8);
  putI32(f, 0, s.max_speed_rpm);
  putI32(f, 4, s.position);
  return f;
}
CanFrame encodeFeedback(int node, const ThorvaldFeedback& fb) {
  CanFrame f = frame(thorvald_ids::kFeedback, node, 8);
  putI16(f, 0, fb.propulsion_rpm);
  putI16(f, 2, fb.steering_rpm);
  putI32(f, 4, fb.steering_count);
  return f;
}
CanFrame encodePower(int node, const ThorvaldPower& p) {
  CanFrame f = frame(thorvald_ids::kPower, node, 8);
  putI16(f, 0, p.current_da[0]);
  putI16(f, 2, p.current_da[1]);
  putI16(f, 4, p.power_permille[0]);
  putI16(f, 6, p.power_permille[1]);
  return f;
}
CanFrame encodeStatus(int node, const ThorvaldStatus& s) {
  CanFrame f = frame(thorvald_ids::kStatus, node, 6);
  f.data[0] = s.flags;
  f.data[1] = static_cast<uint8_t>(s.max_temperature_c);
  putI16(f, 2, s.battery_current_da);
  putU16(f, 4, s.battery_voltage_dv);
  return f;
}
CanFrame encodeInfo(int node, const ThorvaldInfo& i) {
  CanFrame f = frame(thorvald_ids::kInfo, node, 8);
  f.data[3] = i.type;
  if (i.type == 1) {
    f.data[0] = static_cast<uint8_t>(i.home_direction);
    putI16(f, 1, i.home_speed_rpm);
    putI32(f, 4, i.home_count);
  } else if (i.type == 2) {
    f.data[0] = i.controller_type;
    putU16(f, 1, i.script_version);
  } else if (i.type == 3) {
    putI32(f, 4, i.encoder_ppr);
  }
  return f;
}
CanFrame encodeHeartbeat(int node, uint8_t state) {
  CanFrame f = frame(thorvald_ids::kHeartbeat, node, 1);
  f.data[0] = state;
  return f;
}

std::optional<ThorvaldCommand> decodeCommand(const CanFrame& f) {
  if (!is(f, thorvald_ids::kCommand, 8)) return std::nullopt;
  return ThorvaldCommand{getI32(f, 0), getI32(f, 4)};
}
std::optional<ThorvaldSetup> decodeSetup(const CanFrame& f) {
  if (!is(f, thorvald_ids::kSetup, 8)) return std::nullopt;
  return ThorvaldSetup{getI32(f, 0), getI32(f, 4)};
}
std::optional<ThorvaldMode> decodeMode(const CanFrame& f) {
  if (!is(f, thorvald_ids::kMode, 4)) return std::nullopt;
  const int32_t m = getI32(f, 0);
  if (m < 0 || m > 2) return std::nullopt;
  return static_cast<ThorvaldMode>(m);
}
std::optional<ThorvaldSteering> decodeSteering(const CanFrame& f) {
  if (!is(f, thorvald_ids::kSteering, 8)) return std::nullopt;
  return ThorvaldSteering{getI32(f, 0), getI32(f, 4)};
}
std::optional<ThorvaldFeedback> decodeFeedback(const CanFrame& f) {
  if (!is(f, thorvald_ids::kFeedback, 8)) return std::nullopt;
  return ThorvaldFeedback{getI16(f, 0), getI16(f, 2), getI32(f, 4)};
}
std::optional<ThorvaldPower> decodePower(const CanFrame& f) {
  if (!is(f, thorvald_ids::kPower, 8)) return std::nullopt;
  ThorvaldPower p;
  p.current_da[0] = getI16(f, 0);
  p.current_da[1] = getI16(f, 2);
  p.power_permille[0] = getI16(f, 4);
  p.power_permille[1] = getI16(f, 6);
  return p;
}
std::optional<ThorvaldStatus> decodeStatus(const CanFrame& f) {
  if (!is(f, thorvald_ids::kStatus, 6)) return std::nullopt;
  ThorvaldStatus s;
  s.flags = f.data[0];
  s.max_temperature_c = static_cast<int8_t>(f.data[1]);
  s.battery_current_da = getI16(f, 2);
  s.battery_voltage_dv = getU16(f, 4);
  return s;
}
std::optional<ThorvaldInfo> decodeInfo(const CanFrame& f) {
  if (!is(f, thorvald_ids::kInfo, 8)) return std::nullopt;
  ThorvaldInfo i;
  i.type = f.data[3];
  if (i.type == 1) {
    i.home_direction = static_cast<int8_t>(f.data[0]);
    if (i.home_direction < -1 || i.home_direction > 1) return std::nullopt;
    i.home_speed_rpm = getI16(f, 1);
    i.home_count = getI32(f, 4);
  } else if (i.type == 2) {
    i.controller_type = f.data[0];
    if (i.controller_type > 1) return std::nullopt;
    i.script_version = getU16(f, 1);
  } else if (i.type == 3) {
    i.encoder_ppr = getI32(f, 4);
  } else {
    return std::nullopt;  // unknown message type
  }
  return i;
}
std::optional<uint8_t> decodeHeartbeat(const CanFrame& f) {
  if (!is(f, thorvald_ids::kHeartbeat, 1)) return std::nullopt;
  const uint8_t s = f.data[0];
  if (s != kHeartbeatBootUp && s != kHeartbeatStopped && s != kHeartbeatOperational && s != kHeartbeatPreOperational)
    return std::nullopt;
  return s;
}

std::string describeFlags(uint8_t flags) {
  static const struct {
    uint8_t bit;
    const char* text;
  } names[] = {{thorvald_flags::kPropulsionEncoderFault, "propulsion encoder fault"},
               {thorvald_flags::kSteeringEncoderFault, "steering encoder fault"},
               {thorvald_flags::kAlignmentFault, "alignment fault"},
               {thorvald_flags::kPowerStageOff, "power stage off"},
               {thorvald_flags::kStall, "stall"},
               {thorvald_flags::kHomingExceeded, "homing exceeded max count"},
               {thorvald_flags::kIllegalCommand, "illegal command"}};
  std::string out;
  for (const auto& n : names) {
    if (flags & n.bit) out += (out.empty() ? "" : ", ") + std::string(n.text);
  }
  if (!(flags & thorvald_flags::kControllerOk)) out += (out.empty() ? "" : ", ") + std::string("controller not ok");
  return out;
}

}  // namespace thorvald_can_devices
