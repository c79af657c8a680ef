#include "thorvald_can_devices/battery_protocol.h"

namespace thorvald_can_devices {

int batteryIdOf(const CanFrame& f, uint32_t base) {
  if (f.isError() || f.isExtended() || f.isRemote()) return -1;
  const uint32_t id = f.stdId();
  if (id < base || id > base + battery_ids::kMaxId) return -1;
  return static_cast<int>(id - base);
}

CanFrame encodeBatteryState(int id, const BatteryStateFrame& s) {
  CanFrame f;
  f.id = battery_ids::kState + static_cast<uint32_t>(id);
  f.length = 8;
  f.data[0] = s.status;
  f.data[1] = s.fets;
  putU16(f, 2, s.voltage_cv);
  putU16(f, 4, s.alarms);
  f.data[6] = static_cast<uint8_t>(s.temperature_c[0]);
  f.data[7] = static_cast<uint8_t>(s.temperature_c[1]);
  return f;
}
CanFrame encodeBatteryCurrent(int id, const BatteryCurrentFrame& c) {
  CanFrame f;
  f.id = battery_ids::kCurrent + static_cast<uint32_t>(id);
  f.length = 7;
  for (int i = 0; i < 4; ++i) f.data[i] = static_cast<uint8_t>(c.temperature_c[i]);
  putI16(f, 4, c.current_ca);
  f.data[6] = static_cast<uint8_t>(c.temperature_c[4]);
  return f;
}
CanFrame encodeBatteryCharge(int id, const BatteryChargeFrame& c) {
  CanFrame f;
  f.id = battery_ids::kCharge + static_cast<uint32_t>(id);
  f.length = 4;
  f.data[0] = c.charge_pct;
  f.data[1] = c.health_pct;
  putU16(f, 2, c.cycles);
  return f;
}

std::optional<BatteryStateFrame> decodeBatteryState(const CanFrame& f) {
  if (batteryIdOf(f, battery_ids::kState) < 0 || f.length != 8) return std::nullopt;
  BatteryStateFrame s;
  s.status = f.data[0];
  s.fets = f.data[1];
  s.voltage_cv = getU16(f, 2);
  s.alarms = getU16(f, 4);
  s.temperature_c[0] = static_cast<int8_t>(f.data[6]);
  s.temperature_c[1] = static_cast<int8_t>(f.data[7]);
  return s;
}
std::optional<BatteryCurrentFrame> decodeBatteryCurrent(const CanFrame& f) {
  if (batteryIdOf(f, battery_ids::kCurrent) < 0 || f.length != 7) return std::nullopt;
  BatteryCurrentFrame c;
  for (int i = 0; i < 4; ++i) c.temperature_c[i] = static_cast<int8_t>(f.data[i]);
  c.current_ca = getI16(f, 4);
  c.temperature_c[4] = static_cast<int8_t>(f.data[6]);
  return c;
}
std::optional<BatteryChargeFrame> decodeBatteryCharge(const CanFrame& f) {
  if (batteryIdOf(f, battery_ids::kCharge) < 0 || f.length != 4) return std::nullopt;
  BatteryChargeFrame c;
  c.charge_pct = f.data[0];
  c.health_pct = f.data[1];
  c.cycles = getU16(f, 2);
  if (c.charge_pct > 100 || c.health_pct > 100) return std::nullopt;
  return c;
}

}  // namespace thorvald_can_devices
