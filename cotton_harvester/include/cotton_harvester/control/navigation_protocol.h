#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace cotton_harvester {
namespace control {

/// Frames between the host and the rover's navigation controller (README, "Control").
///
/// Drive command, host -> controller, 6 bytes, at the control rate (50 Hz):
///   0xAA, 0x43 ('C'), swashplate servo PWM (uint8, 65..120), relays (bit 0 left, bit 1 right),
///   sequence number (uint8, wraps), XOR of bytes 1..4.
/// Telemetry, controller -> host, 10 bytes, at 50 Hz:
///   0xAA, 0x54 ('T'), encoder count (int32, little endian, 1.8 mm per pulse), potentiometer
///   (uint16 little endian, ADC counts), flags (bit 0: watchdog stop, no command for 0.5 s;
///   bit 1: PWM out of 65..120 was clamped), XOR of bytes 1..8.
constexpr std::uint8_t kNavigationSync = 0xAA;
constexpr std::uint8_t kDriveCommandType = 0x43;
constexpr std::uint8_t kTelemetryType = 0x54;
constexpr std::size_t kDriveCommandSize = 6;
constexpr std::size_t kTelemetrySize = 10;

struct DriveCommand {
  std::uint8_t pwm = 90;
  bool relay_left = false;
  bool relay_right = false;
  std::uint8_t sequence = 0;
};

struct Telemetry {
  std::int32_t encoder_count = 0;
  std::uint16_t pot_counts = 0;
  bool watchdog_stop = false;
  bool pwm_clamped = false;
};

std::vector<std::uint8_t> encodeDriveCommand(const DriveCommand& command);
std::vector<std::uint8_t> encodeTelemetry(const Telemetry& telemetry);

/// Splits a byte stream into drive commands and telemetry frames (checksum checked).
class NavigationFrameParser {
 public:
  void push(const std::uint8_t* data, std::size_t size);
  std::vector<DriveCommand> takeCommands();
  std::vector<Telemetry> takeTelemetry();
  std::size_t rejectedBytes() const { return rejected_; }

 private:
  std::vector<std::uint8_t> buffer_;
  std::vector<DriveCommand> commands_;
  std::vector<Telemetry> telemetry_;
  std::size_t rejected_ = 0;
};

}  // namespace control
}  // namespace cotton_harvester
