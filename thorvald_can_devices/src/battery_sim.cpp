#include "thorvald_can_devices/battery_sim.h"

#include <cmath>

#include "thorvald_can_devices/battery_protocol.h"

namespace thorvald_can_devices {

BatterySim::BatterySim(const thorvald_base::BatteryConfig& config) : id_(config.id) {}

void BatterySim::setFault(const std::string& fault, bool active) {
  if (fault == "silent") silent_ = active;
  if (fault == "alarm") alarms_ = active ? battery_alarms::kOverTemperature : 0;
}

void BatterySim::step(double now_s, CanBus& bus) {
  if (silent_ || now_s < next_s_) return;
  next_s_ = now_s + period_s;
  const auto t = static_cast<int8_t>(std::lround(alarms_ ? 65.0 : temperature_c));
  BatteryStateFrame s;
  s.status = 0x01;
  s.fets = alarms_ ? 0x00 : 0x03;
  s.voltage_cv = static_cast<uint16_t>(clampToI32(voltage_v * 100.0, 0, 65535));
  s.alarms = alarms_;
  s.temperature_c[0] = t;
  s.temperature_c[1] = static_cast<int8_t>(t + 1);
  bus.send(encodeBatteryState(id_, s));
  BatteryCurrentFrame c;
  for (int i = 0; i < 5; ++i) c.temperature_c[i] = static_cast<int8_t>(t + 2 + i);
  c.current_ca = static_cast<int16_t>(clampToI32(current_a * 100.0, -32768, 32767));
  bus.send(encodeBatteryCurrent(id_, c));
  BatteryChargeFrame ch;
  ch.charge_pct = static_cast<uint8_t>(clampToI32(charge_pct, 0, 100));
  ch.health_pct = static_cast<uint8_t>(clampToI32(health_pct, 0, 100));
  ch.cycles = static_cast<uint16_t>(cycles);
  bus.send(encodeBatteryCharge(id_, ch));
}

}  // namespace thorvald_can_devices
