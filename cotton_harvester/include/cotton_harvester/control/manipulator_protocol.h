#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cotton_harvester/control/manipulator_calibration.h"

namespace cotton_harvester {
namespace control {

/// The 4-byte frames between the host and the manipulation controller (README, "Control").
///
/// Command, host -> controller:
///   byte 0  0xA0 | target << 2 | direction     target: 0 horizontal, 1 vertical, 2 brush, 3 control
///                                              direction (moves): 1 = step counter increases
///   byte 1  moves: steps, high byte            brush: 1 on, 0 off     control: 0 query, 1 stop
///   byte 2  moves: steps, low byte             otherwise 0
///   byte 3  XOR of bytes 0..2
/// Report, controller -> host (after a move ends, every 100 ms while an axis moves, on a query):
///   byte 0  0xB0 | target << 2 | moving << 1 | limit    target: 0 horizontal, 1 vertical, 2 brush
///   byte 1  position in steps (int16) high byte          brush: 1 on, 0 off
///   byte 2  position low byte                            brush: 0
///   byte 3  XOR of bytes 0..2
using ManipulatorFrame = std::array<std::uint8_t, 4>;

struct ManipulatorCommand {
  enum class Kind : std::uint8_t { kMove, kBrush, kQuery, kStop };
  Kind kind = Kind::kQuery;
  StepMove move;          ///< for kMove
  bool brush_on = false;  ///< for kBrush
};

struct ManipulatorReport {
  enum class Target : std::uint8_t { kHorizontal = 0, kVertical = 1, kBrush = 2 };
  Target target = Target::kHorizontal;
  std::int16_t position_steps = 0;  ///< absolute step counter of the axis
  bool moving = false;
  bool limit = false;     ///< the last move stopped at the axis end before its step count
  bool brush_on = false;  ///< for kBrush
};

ManipulatorFrame encodeCommand(const ManipulatorCommand& command);
ManipulatorFrame encodeReport(const ManipulatorReport& report);
/// Decoding of one frame whose checksum was already checked; false when the bytes make no frame.
bool decodeCommand(const ManipulatorFrame& frame, ManipulatorCommand* command);
bool decodeReport(const ManipulatorFrame& frame, ManipulatorReport* report);

/// Splits a byte stream into 4-byte frames whose first byte has the given high nibble (0xA0 for
/// commands, 0xB0 for reports) and whose checksum matches; skips garbage one byte at a time.
class ManipulatorFrameParser {
 public:
  explicit ManipulatorFrameParser(std::uint8_t sync_nibble) : sync_(sync_nibble & 0xF0) {}
  /// Feeds bytes; returns the complete, valid frames found.
  std::vector<ManipulatorFrame> push(const std::uint8_t* data, std::size_t size);
  std::size_t rejectedBytes() const { return rejected_; }

 private:
  std::uint8_t sync_;
  std::vector<std::uint8_t> buffer_;
  std::size_t rejected_ = 0;
};

}  // namespace control
}  // namespace cotton_harvester
