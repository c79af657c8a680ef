#include "cotton_harvester/control/manipulator_protocol.h"

namespace cotton_harvester {
namespace control {
namespace {

std::uint8_t checksum(const ManipulatorFrame& frame) { return frame[0] ^ frame[1] ^ frame[2]; }

ManipulatorFrame withChecksum(std::uint8_t b0, std::uint8_t b1, std::uint8_t b2) {
  ManipulatorFrame frame{b0, b1, b2, 0};
  frame[3] = checksum(frame);
  return frame;
}

}  // namespace

ManipulatorFrame encodeCommand(const ManipulatorCommand& command) {
  switch (command.kind) {
    case ManipulatorCommand::Kind::kMove: {
      const std::uint8_t target = static_cast<std::uint8_t>(command.move.axis);
      return withChecksum(0xA0 | target << 2 | (command.move.positive ? 1 : 0), command.move.steps >> 8,
                          command.move.steps & 0xFF);
    }
    case ManipulatorCommand::Kind::kBrush:
      return withChecksum(0xA0 | 2 << 2, command.brush_on ? 1 : 0, 0);
    case ManipulatorCommand::Kind::kStop:
      return withChecksum(0xA0 | 3 << 2, 1, 0);
    case ManipulatorCommand::Kind::kQuery:
    default:
      return withChecksum(0xA0 | 3 << 2, 0, 0);
  }
}

bool decodeCommand(const ManipulatorFrame& frame, ManipulatorCommand* command) {
  if ((frame[0] & 0xF0) != 0xA0 || checksum(frame) != frame[3]) return false;
  const int target = (frame[0] >> 2) & 0x3;
  ManipulatorCommand decoded;
  if (target <= 1) {
    if (frame[0] & 0x02) return false;  // reserved bit
    decoded.kind = ManipulatorCommand::Kind::kMove;
    decoded.move.axis = target == 0 ? Axis::kHorizontal : Axis::kVertical;
    decoded.move.positive = frame[0] & 0x01;
    decoded.move.steps = static_cast<std::uint16_t>(frame[1] << 8 | frame[2]);
  } else if (target == 2) {
    if (frame[1] > 1 || frame[2] != 0 || (frame[0] & 0x03)) return false;
    decoded.kind = ManipulatorCommand::Kind::kBrush;
    decoded.brush_on = frame[1] == 1;
  } else {
    if (frame[1] > 1 || frame[2] != 0 || (frame[0] & 0x03)) return false;
    decoded.kind = frame[1] == 1 ? ManipulatorCommand::Kind::kStop : ManipulatorCommand::Kind::kQuery;
  }
  *command = decoded;
  return true;
}

ManipulatorFrame encodeReport(const ManipulatorReport& report) {
  const std::uint8_t b0 =
      0xB0 | static_cast<std::uint8_t>(report.target) << 2 | (report.moving ? 2 : 0) | (report.limit ? 1 : 0);
  if (report.target == ManipulatorReport::Target::kBrush) return withChecksum(b0, report.brush_on ? 1 : 0, 0);
  const auto position = static_cast<std::uint16_t>(report.position_steps);
  return withChecksum(b0, position >> 8, position & 0xFF);
}

bool decodeReport(const ManipulatorFrame& frame, ManipulatorReport* report) {
  if ((frame[0] & 0xF0) != 0xB0 || checksum(frame) != frame[3]) return false;
  const int target = (frame[0] >> 2) & 0x3;
  if (target == 3) return false;
  ManipulatorReport decoded;
  decoded.target = static_cast<ManipulatorReport::Target>(target);
  decoded.moving = frame[0] & 0x02;
  decoded.limit = frame[0] & 0x01;
  if (decoded.target == ManipulatorReport::Target::kBrush) {
    decoded.brush_on = frame[1] == 1;
  } else {
    decoded.position_steps = static_cast<std::int16_t>(static_cast<std::uint16_t>(frame[1] << 8 | frame[2]));
  }
  *report = decoded;
  return true;
}

std::vector<ManipulatorFrame> ManipulatorFrameParser::push(const std::uint8_t* data, std::size_t size) {
  buffer_.insert(buffer_.end(), data, data + size);
  std::vector<ManipulatorFrame> frames;
  std::size_t start = 0;
  while (buffer_.size() - start >= 4) {
    ManipulatorFrame frame{buffer_[start], buffer_[start + 1], buffer_[start + 2], buffer_[start + 3]};
    if ((frame[0] & 0xF0) == sync_ && checksum(frame) == frame[3]) {
      frames.push_back(frame);
      start += 4;
    } else {
      ++rejected_;
      ++start;
    }
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(start));
  return frames;
}

}  // namespace control
}  // namespace cotton_harvester
