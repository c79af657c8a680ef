#include "decoders.h"

#include <string>

#include "thorvald_can_devices/battery_protocol.h"
#include "thorvald_can_devices/bus_error.h"
#include "thorvald_can_devices/candump_log.h"
#include "thorvald_can_devices/canopen_protocol.h"
#include "thorvald_can_devices/thorvald_drive_protocol.h"
#include "thorvald_can_devices/virtual_can_bus.h"

namespace thorvald_can_devices {
namespace {

CanFrame frameFrom(const uint8_t* data, size_t size) {
  CanFrame f;
  if (size >= 2) f.id = static_cast<uint32_t>(data[0] | (data[1] << 8)) & 0x7FF;
  if (size >= 3) f.length = data[2];  // may be above 8: decoders must reject it
  for (size_t i = 3; i < size && i < 11; ++i) f.data[i - 3] = data[i];
  return f;
}

void check(bool ok) {
  if (!ok) __builtin_trap();
}

/// decode -> encode -> decode -> encode gives the same frame twice.
template <typename Decode, typename Encode>
void roundTrip(const CanFrame& f, Decode decode, Encode encode) {
  const auto first = decode(f);
  if (!first) return;
  const CanFrame e1 = encode(*first);
  const auto second = decode(e1);
  check(second.has_value());
  check(encode(*second) == e1);
}

}  // namespace

void fuzzThorvaldFrames(const uint8_t* data, size_t size) {
  const CanFrame f = frameFrom(data, size);
  const int n = f.stdId() & 0x7F;
  roundTrip(f, decodeCommand, [&](const ThorvaldCommand& c) { return encodeCommand(n, c); });
  roundTrip(f, decodeSetup, [&](const ThorvaldSetup& s) { return encodeSetup(n, s); });
  roundTrip(f, decodeMode, [&](ThorvaldMode m) { return encodeMode(n, m); });
  roundTrip(f, decodeSteering, [&](const ThorvaldSteering& s) { return encodeSteering(n, s); });
  roundTrip(f, decodeFeedback, [&](const ThorvaldFeedback& b) { return encodeFeedback(n, b); });
  roundTrip(f, decodePower, [&](const ThorvaldPower& p) { return encodePower(n, p); });
  roundTrip(f, decodeStatus, [&](const ThorvaldStatus& s) { return encodeStatus(n, s); });
  roundTrip(f, decodeInfo, [&](const ThorvaldInfo& i) { return encodeInfo(n, i); });
  roundTrip(f, decodeHeartbeat, [&](uint8_t s) { return encodeHeartbeat(n, s); });
  if (auto st = decodeStatus(f)) (void)describeFlags(st->flags);
}

void fuzzBatteryFrames(const uint8_t* data, size_t size) {
  const CanFrame f = frameFrom(data, size);
  const int id = f.stdId() & 0x0F;
  roundTrip(f, decodeBatteryState, [&](const BatteryStateFrame& s) { return encodeBatteryState(id, s); });
  roundTrip(f, decodeBatteryCurrent, [&](const BatteryCurrentFrame& c) { return encodeBatteryCurrent(id, c); });
  roundTrip(f, decodeBatteryCharge, [&](const BatteryChargeFrame& c) { return encodeBatteryCharge(id, c); });
}

void fuzzCanopenFrames(const uint8_t* data, size_t size) {
  CanFrame f = frameFrom(data, size);
  const int n = f.stdId() & 0x7F;
  roundTrip(f, decodeNmt, [&](const NmtMessage& m) { return encodeNmt(m.command, m.node); });
  roundTrip(f, decodeEmergency, [&](const Emergency& e) { return encodeEmergency(n, e); });
  const bool request = (f.stdId() & 0x780) == 0x600;
  roundTrip(f, decodeSdo, [&](const SdoMessage& m) { return request ? encodeSdoRequest(n, m) : encodeSdoReply(n, m); });
  roundTrip(f, decodeRpdo1, [&](const Cia402Rpdo1& p) { return encodeRpdo1(n, p); });
  roundTrip(f, decodeTpdo1, [&](const Cia402Tpdo1& p) { return encodeTpdo1(n, p); });
  roundTrip(f, decodeTpdo2, [&](const Cia402Tpdo2& p) { return encodeTpdo2(n, p); });
  if (size >= 2) {
    const uint16_t sw = static_cast<uint16_t>(data[0] | (data[1] << 8));
    (void)toString(stateOf(sw));
    (void)nextState(stateOf(sw), sw);
  }
  // The same bytes as an error frame and as a virtual-bus record.
  f.id |= kCanErrorFlag;
  (void)decodeBusError(f);
  CanFrame r;
  (void)decodeRecord(data, size, &r);
}

void fuzzCandumpLine(const uint8_t* data, size_t size) {
  const std::string line(reinterpret_cast<const char*>(data), size);
  double t = 0;
  std::string iface;
  CanFrame f;
  if (!parseCandumpLine(line, &t, &iface, &f)) return;
  check(f.length <= 8);
  if (iface.find(' ') != std::string::npos || iface.empty()) return;
  // What we write, we read back the same.
  double t2 = 0;
  std::string iface2;
  CanFrame f2;
  const std::string again = formatCandumpLine(t, iface, f);
  check(parseCandumpLine(again, &t2, &iface2, &f2));
  check(f2 == f && iface2 == iface);
}

}  // namespace thorvald_can_devices
