#include <gtest/gtest.h>

#include "cotton_harvester/control/manipulator_protocol.h"
#include "cotton_harvester/control/navigation_protocol.h"

using namespace cotton_harvester::control;

TEST(ManipulatorProtocol, CommandBytesByValue) {
  ManipulatorCommand command;
  command.kind = ManipulatorCommand::Kind::kMove;
  command.move = StepMove{Axis::kVertical, true, 278};
  EXPECT_EQ(encodeCommand(command), (ManipulatorFrame{0xA5, 0x01, 0x16, 0xB2}));
  command.move = StepMove{Axis::kHorizontal, false, 2000};  // 0x07D0
  EXPECT_EQ(encodeCommand(command), (ManipulatorFrame{0xA0, 0x07, 0xD0, 0xA0 ^ 0x07 ^ 0xD0}));
  ManipulatorCommand brush;
  brush.kind = ManipulatorCommand::Kind::kBrush;
  brush.brush_on = true;
  EXPECT_EQ(encodeCommand(brush), (ManipulatorFrame{0xA8, 0x01, 0x00, 0xA9}));
  ManipulatorCommand query;
  EXPECT_EQ(encodeCommand(query), (ManipulatorFrame{0xAC, 0x00, 0x00, 0xAC}));
  ManipulatorCommand stop;
  stop.kind = ManipulatorCommand::Kind::kStop;
  EXPECT_EQ(encodeCommand(stop), (ManipulatorFrame{0xAC, 0x01, 0x00, 0xAD}));
}

TEST(ManipulatorProtocol, CommandsRoundTrip) {
  for (auto axis : {Axis::kHorizontal, Axis::kVertical}) {
    for (bool positive : {true, false}) {
      ManipulatorCommand command;
      command.kind = ManipulatorCommand::Kind::kMove;
      command.move = StepMove{axis, positive, 65535};
      ManipulatorCommand decoded;
      ASSERT_TRUE(decodeCommand(encodeCommand(command), &decoded));
      EXPECT_EQ(decoded.kind, ManipulatorCommand::Kind::kMove);
      EXPECT_EQ(decoded.move.axis, axis);
      EXPECT_EQ(decoded.move.positive, positive);
      EXPECT_EQ(decoded.move.steps, 65535);
    }
  }
  ManipulatorCommand decoded;
  EXPECT_FALSE(decodeCommand(ManipulatorFrame{0xA5, 0x01, 0x16, 0x00}, &decoded));                // checksum
  EXPECT_FALSE(decodeCommand(ManipulatorFrame{0xB5, 0x01, 0x16, 0xB5 ^ 0x01 ^ 0x16}, &decoded));  // a report
  EXPECT_FALSE(decodeCommand(ManipulatorFrame{0xA8, 0x05, 0x00, 0xA8 ^ 0x05}, &decoded));         // brush value
}

TEST(ManipulatorProtocol, ReportBytesByValue) {
  ManipulatorReport report;
  report.target = ManipulatorReport::Target::kVertical;
  report.position_steps = 278;
  report.moving = true;
  EXPECT_EQ(encodeReport(report), (ManipulatorFrame{0xB6, 0x01, 0x16, 0xA1}));
  report.target = ManipulatorReport::Target::kHorizontal;
  report.position_steps = -2;
  report.moving = false;
  report.limit = true;
  const auto frame = encodeReport(report);
  EXPECT_EQ(frame, (ManipulatorFrame{0xB1, 0xFF, 0xFE, 0xB1 ^ 0xFF ^ 0xFE}));
  ManipulatorReport decoded;
  ASSERT_TRUE(decodeReport(frame, &decoded));
  EXPECT_EQ(decoded.position_steps, -2);
  EXPECT_TRUE(decoded.limit);
  EXPECT_FALSE(decoded.moving);
}

TEST(ManipulatorProtocol, ParserResynchronisesAfterGarbageAndSplits) {
  ManipulatorFrameParser parser(0xB0);
  ManipulatorReport report;
  report.target = ManipulatorReport::Target::kVertical;
  report.position_steps = 300;
  const auto good = encodeReport(report);
  std::vector<std::uint8_t> stream{0x00, 0xB6, 0x13};  // noise, including a false sync byte
  stream.insert(stream.end(), good.begin(), good.end());
  stream.insert(stream.end(), {0xB4, 0x00, 0x00, 0x00});  // bad checksum
  stream.insert(stream.end(), good.begin(), good.end());
  std::vector<ManipulatorFrame> frames;
  for (std::size_t i = 0; i < stream.size(); i += 3) {  // arrives in pieces
    const auto part = parser.push(stream.data() + i, std::min<std::size_t>(3, stream.size() - i));
    frames.insert(frames.end(), part.begin(), part.end());
  }
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0], good);
  EXPECT_EQ(frames[1], good);
  EXPECT_EQ(parser.rejectedBytes(), 3u + 4u);
}

TEST(NavigationProtocol, FramesByValue) {
  DriveCommand command;
  command.pwm = 103;
  command.relay_left = true;
  command.sequence = 7;
  EXPECT_EQ(encodeDriveCommand(command), (std::vector<std::uint8_t>{0xAA, 0x43, 0x67, 0x01, 0x07, 0x22}));
  Telemetry telemetry;
  telemetry.encoder_count = -2;
  telemetry.pot_counts = 600;
  telemetry.watchdog_stop = true;
  EXPECT_EQ(encodeTelemetry(telemetry),
            (std::vector<std::uint8_t>{0xAA, 0x54, 0xFE, 0xFF, 0xFF, 0xFF, 0x58, 0x02, 0x01, 0x0E}));
}

TEST(NavigationProtocol, ParserSplitsMixedStreams) {
  NavigationFrameParser parser;
  Telemetry telemetry;
  telemetry.encoder_count = 123456;
  telemetry.pot_counts = 1023;
  telemetry.pwm_clamped = true;
  DriveCommand command;
  command.pwm = 75;
  command.relay_right = true;
  command.sequence = 255;
  std::vector<std::uint8_t> stream{0x13, 0xAA};  // noise and a lone sync byte
  for (auto part : {encodeTelemetry(telemetry), encodeDriveCommand(command), encodeTelemetry(telemetry)})
    stream.insert(stream.end(), part.begin(), part.end());
  auto corrupt = encodeTelemetry(telemetry);
  corrupt[4] ^= 0x10;
  stream.insert(stream.end(), corrupt.begin(), corrupt.end());
  for (std::size_t i = 0; i < stream.size(); ++i) parser.push(&stream[i], 1);  // byte by byte
  const auto telemetries = parser.takeTelemetry();
  const auto commands = parser.takeCommands();
  ASSERT_EQ(telemetries.size(), 2u);
  EXPECT_EQ(telemetries[1].encoder_count, 123456);
  EXPECT_EQ(telemetries[1].pot_counts, 1023);
  EXPECT_TRUE(telemetries[1].pwm_clamped);
  EXPECT_FALSE(telemetries[1].watchdog_stop);
  ASSERT_EQ(commands.size(), 1u);
  EXPECT_EQ(commands[0].pwm, 75);
  EXPECT_TRUE(commands[0].relay_right);
  EXPECT_FALSE(commands[0].relay_left);
  EXPECT_EQ(commands[0].sequence, 255);
  EXPECT_GE(parser.rejectedBytes(), 2u + 1u);
  EXPECT_TRUE(parser.takeTelemetry().empty());
}
