#include "cotton_harvester/control/navigation_protocol.h"

namespace cotton_harvester {
namespace control {
namespace {

std::uint8_t xorOf(const std::uint8_t* bytes, std::size_t first, std::size_t last) {
  std::uint8_t sum = 0;
  for (std::size_t i = first; i <= last; ++i) sum ^= bytes[i];
  return sum;
}

}  // namespace

std::vector<std::uint8_t> encodeDriveCommand(const DriveCommand& command) {
  std::vector<std::uint8_t> frame{
      kNavigationSync,  kDriveCommandType,
      command.pwm,      static_cast<std::uint8_t>((command.relay_left ? 1 : 0) | (command.relay_right ? 2 : 0)),
      command.sequence, 0};
  frame[5] = xorOf(frame.data(), 1, 4);
  return frame;
}

std::vector<std::uint8_t> encodeTelemetry(const Telemetry& telemetry) {
  const auto count = static_cast<std::uint32_t>(telemetry.encoder_count);
  std::vector<std::uint8_t> frame{
      kNavigationSync,
      kTelemetryType,
      static_cast<std::uint8_t>(count & 0xFF),
      static_cast<std::uint8_t>(count >> 8 & 0xFF),
      static_cast<std::uint8_t>(count >> 16 & 0xFF),
      static_cast<std::uint8_t>(count >> 24 & 0xFF),
      static_cast<std::uint8_t>(telemetry.pot_counts & 0xFF),
      static_cast<std::uint8_t>(telemetry.pot_counts >> 8),
      static_cast<std::uint8_t>((telemetry.watchdog_stop ? 1 : 0) | (telemetry.pwm_clamped ? 2 : 0)),
      0};
  frame[9] = xorOf(frame.data(), 1, 8);
  return frame;
}

void NavigationFrameParser::push(const std::uint8_t* data, std::size_t size) {
  buffer_.insert(buffer_.end(), data, data + size);
  std::size_t start = 0;
  while (buffer_.size() - start >= 2) {
    const std::uint8_t* frame = buffer_.data() + start;
    std::size_t length = 0;
    if (frame[0] == kNavigationSync && frame[1] == kDriveCommandType) length = kDriveCommandSize;
    if (frame[0] == kNavigationSync && frame[1] == kTelemetryType) length = kTelemetrySize;
    if (length == 0) {
      ++rejected_;
      ++start;
      continue;
    }
    if (buffer_.size() - start < length) break;
    if (xorOf(frame, 1, length - 2) != frame[length - 1] || (length == kDriveCommandSize && frame[3] > 3) ||
        (length == kTelemetrySize && frame[8] > 3)) {
      ++rejected_;
      ++start;
      continue;
    }
    if (length == kDriveCommandSize) {
      DriveCommand command;
      command.pwm = frame[2];
      command.relay_left = frame[3] & 1;
      command.relay_right = frame[3] & 2;
      command.sequence = frame[4];
      commands_.push_back(command);
    } else {
      Telemetry telemetry;
      const std::uint32_t count = static_cast<std::uint32_t>(frame[2]) | static_cast<std::uint32_t>(frame[3]) << 8 |
                                  static_cast<std::uint32_t>(frame[4]) << 16 |
                                  static_cast<std::uint32_t>(frame[5]) << 24;
      telemetry.encoder_count = static_cast<std::int32_t>(count);
      telemetry.pot_counts = static_cast<std::uint16_t>(frame[6] | frame[7] << 8);
      telemetry.watchdog_stop = frame[8] & 1;
      telemetry.pwm_clamped = frame[8] & 2;
      telemetry_.push_back(telemetry);
    }
    start += length;
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(start));
}

std::vector<DriveCommand> NavigationFrameParser::takeCommands() {
  std::vector<DriveCommand> out;
  out.swap(commands_);
  return out;
}

std::vector<Telemetry> NavigationFrameParser::takeTelemetry() {
  std::vector<Telemetry> out;
  out.swap(telemetry_);
  return out;
}

}  // namespace control
}  // namespace cotton_harvester
