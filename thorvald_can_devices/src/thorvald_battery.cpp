#include "thorvald_can_devices/thorvald_battery.h"

#include <cmath>

namespace thorvald_can_devices {

ThorvaldBattery::ThorvaldBattery(const thorvald_base::BatteryConfig& config) : name_(config.name), id_(config.id) {
  reading_.temperatures_c.assign(7, std::nan(""));
  reading_.voltage_v = std::nan("");
  reading_.current_a = std::nan("");
  reading_.charge_pct = std::nan("");
  reading_.health_pct = std::nan("");
}

std::vector<uint32_t> ThorvaldBattery::receiveIds() const {
  const uint32_t i = static_cast<uint32_t>(id_);
  return {battery_ids::kState + i, battery_ids::kCurrent + i, battery_ids::kCharge + i};
}

void ThorvaldBattery::handle(const CanFrame& f, double now_s) {
  now_s_ = now_s;
  const uint32_t base = f.stdId() - static_cast<uint32_t>(id_);
  bool ok = false;
  if (base == battery_ids::kState) {
    if (auto s = decodeBatteryState(f)) {
      ok = true;
      reading_.present = (s->status & 0x01) != 0;
      reading_.charging_enabled = (s->fets & 0x01) != 0;
      reading_.discharging_enabled = (s->fets & 0x02) != 0;
      reading_.voltage_v = s->voltage_cv / 100.0;
      reading_.alarms = s->alarms;
      reading_.temperatures_c[0] = s->temperature_c[0];
      reading_.temperatures_c[1] = s->temperature_c[1];
    }
  } else if (base == battery_ids::kCurrent) {
    if (auto c = decodeBatteryCurrent(f)) {
      ok = true;
      reading_.current_a = c->current_ca / 100.0;
      for (int i = 0; i < 5; ++i) reading_.temperatures_c[2 + i] = c->temperature_c[i];
    }
  } else if (base == battery_ids::kCharge) {
    if (auto c = decodeBatteryCharge(f)) {
      ok = true;
      reading_.charge_pct = c->charge_pct;
      reading_.health_pct = c->health_pct;
      reading_.cycles = c->cycles;
    }
  }
  if (ok) {
    heard_ = true;
    last_frame_s_ = now_s;
  } else {
    ++malformed_;
  }
}

thorvald_base::BatteryReading ThorvaldBattery::reading() const {
  thorvald_base::BatteryReading r = reading_;
  r.online = operational();
  r.age_s = heard_ ? now_s_ - last_frame_s_ : -1.0;
  return r;
}

}  // namespace thorvald_can_devices
