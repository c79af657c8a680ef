#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace thorvald_base {

/// One reading of a battery enclosure. NaN where the enclosure does not report a value.
struct BatteryReading {
  bool online = false;                 ///< frames arrive
  bool present = true;                 ///< a battery is fitted
  double voltage_v = 0.0;              ///< [V]
  double current_a = 0.0;              ///< [A], positive when charging
  double charge_pct = 0.0;             ///< state of charge [%]
  double health_pct = 0.0;             ///< state of health [%]
  int cycles = 0;                      ///< charge cycle count
  std::vector<double> temperatures_c;  ///< [degC]
  uint16_t alarms = 0;                 ///< enclosure alarm bits
  bool charging_enabled = false;
  bool discharging_enabled = false;
  double age_s = -1.0;  ///< time since the last frame [s]; -1 when unknown (the values are stale when !online)
};

/// A battery enclosure on the robot: a device on the bus or a simulated pack.
class Battery {
 public:
  virtual ~Battery() = default;
  virtual const std::string& name() const = 0;  ///< batN of the robot file
  virtual void update(double now_s) = 0;
  virtual BatteryReading reading() const = 0;
};

}  // namespace thorvald_base
