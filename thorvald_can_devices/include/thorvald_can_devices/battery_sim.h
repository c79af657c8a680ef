#pragma once

#include <cstdint>
#include <string>

#include "thorvald_base/robot_config.h"
#include "thorvald_can_devices/can_bus.h"

namespace thorvald_can_devices {
/// A simulated battery enclosure sending its three frames every `period_s`.
class BatterySim {
 public:
  explicit BatterySim(const thorvald_base::BatteryConfig& config);
  void step(double now_s, CanBus& bus);
  void setFault(const std::string& fault, bool active);
  int id() const { return id_; }
  double voltage_v = 51.2, current_a = -3.5, charge_pct = 87.0, health_pct = 96.0, temperature_c = 24.0;
  int cycles = 132;
  double period_s = 0.2;

 private:
  int id_;
  bool silent_ = false;
  uint16_t alarms_ = 0;
  double next_s_ = 0.0;
};

}  // namespace thorvald_can_devices
