#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "thorvald_can_devices/can_frame.h"

namespace thorvald_can_devices {

/// Broadcast frames of the Thorvald battery enclosure; id = base + battery id (0..15). Layouts: README.
namespace battery_ids {
constexpr uint32_t kState = 0x3C0;    ///< FETs, voltage, alarms, temperatures 0-1
constexpr uint32_t kCurrent = 0x3D0;  ///< temperatures 2-6, current
constexpr uint32_t kCharge = 0x3E0;   ///< state of charge, health, cycles
constexpr int kMaxId = 15;
}  // namespace battery_ids

/// 0x3C0 + id, 8 bytes.
struct BatteryStateFrame {
  uint8_t status = 0;                ///< byte 0: bit 0 battery present
  uint8_t fets = 0;                  ///< byte 1: bit 0 charge FET on, bit 1 discharge FET on
  uint16_t voltage_cv = 0;           ///< bytes 2-3: [V x 100]
  uint16_t alarms = 0;               ///< bytes 4-5: alarm bits (README)
  int8_t temperature_c[2] = {0, 0};  ///< bytes 6-7: temperatures 0-1 [degC]
};
/// 0x3D0 + id, 7 bytes.
struct BatteryCurrentFrame {
  int8_t temperature_c[5] = {0, 0, 0, 0, 0};  ///< temperatures 2-5 in bytes 0-3, temperature 6 in byte 6 [degC]
  int16_t current_ca = 0;                     ///< bytes 4-5: [A x 100], positive charging
};
/// 0x3E0 + id, 4 bytes.
struct BatteryChargeFrame {
  uint8_t charge_pct = 0;  ///< byte 0: state of charge [%], 0..100
  uint8_t health_pct = 0;  ///< byte 1: state of health [%], 0..100
  uint16_t cycles = 0;     ///< bytes 2-3: charge cycle count
};

/// Alarm bits of BatteryStateFrame::alarms.
namespace battery_alarms {
constexpr uint16_t kCellOverVoltage = 0x0001, kCellUnderVoltage = 0x0002, kOverCurrentCharge = 0x0004,
                   kOverCurrentDischarge = 0x0008, kOverTemperature = 0x0010, kUnderTemperature = 0x0020,
                   kShortCircuit = 0x0040, kCellImbalance = 0x0080;
}  // namespace battery_alarms

CanFrame encodeBatteryState(int id, const BatteryStateFrame& s);
CanFrame encodeBatteryCurrent(int id, const BatteryCurrentFrame& c);
CanFrame encodeBatteryCharge(int id, const BatteryChargeFrame& c);
std::optional<BatteryStateFrame> decodeBatteryState(const CanFrame& f);
std::optional<BatteryCurrentFrame> decodeBatteryCurrent(const CanFrame& f);
/// Rejects a charge or health above 100 %.
std::optional<BatteryChargeFrame> decodeBatteryCharge(const CanFrame& f);
/// Battery id of a frame of one of the three kinds, or -1.
int batteryIdOf(const CanFrame& f, uint32_t base);

}  // namespace thorvald_can_devices
