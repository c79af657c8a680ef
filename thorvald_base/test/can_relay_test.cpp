// CanRelay: the decisions of base_driver's CAN relay, without ROS.
#include <gtest/gtest.h>

#include <deque>

#include "thorvald_base/can_relay.h"
#include "thorvald_base/robot_config.h"

namespace thorvald_base {
namespace {

/// A bus that records what is sent, refuses what `refuse_id` names, and hands back the frames queued in `incoming`.
class FakeBus : public BaseHardware {
 public:
  void initialize(const RobotConfig&, const std::string&, const std::string&) override {}
  std::vector<std::unique_ptr<MotorDrive>> takeDrives() override { return {}; }
  std::vector<std::unique_ptr<Battery>> takeBatteries() override { return {}; }
  void poll(double) override {}
  std::vector<CanFrameData> takeRelayFrames() override {
    std::vector<CanFrameData> out(incoming.begin(), incoming.end());
    incoming.clear();
    return out;
  }
  bool sendRelayFrame(const CanFrameData& frame, std::string* why) override {
    if (frame.id == refuse_id) {
      *why = "malformed frame";
      return false;
    }
    sent.push_back(frame);
    return true;
  }
  std::vector<std::pair<std::string, std::string>> diagnostics() const override { return {}; }
  bool busOk() const override { return true; }

  std::vector<CanFrameData> sent;
  std::deque<CanFrameData> incoming;
  uint32_t refuse_id = 0xFFFFFFFF;
};

CanFrameData frame(uint32_t id, uint8_t first_byte = 0) {
  CanFrameData f;
  f.id = id;
  f.length = 1;
  f.data[0] = first_byte;
  return f;
}

using Kind = RelayVerdict::Kind;

TEST(CanRelay, SendsAllowedIdsAndRefusesTheRest) {
  FakeBus bus;
  CanRelay relay(bus, {0x123, 0x124}, {});
  EXPECT_EQ(relay.offer("/user", frame(0x123, 0xAA)).kind, Kind::kSent);
  const RelayVerdict refused = relay.offer("/user", frame(0x201));  // a drive's command id: not allowed
  EXPECT_EQ(refused.kind, Kind::kRefused);
  EXPECT_NE(refused.why.find("allow-list"), std::string::npos) << refused.why;
  EXPECT_EQ(refused.refused_from_sender, 1u);
  EXPECT_EQ(relay.offer("/user", frame(0x000)).refused_from_sender, 2u);  // NMT
  ASSERT_EQ(bus.sent.size(), 1u);
  EXPECT_EQ(bus.sent[0].id, 0x123u);
  EXPECT_EQ(bus.sent[0].data[0], 0xAA);
  EXPECT_EQ(relay.counters().sent, 1u);
  EXPECT_EQ(relay.counters().refused, 2u);
  EXPECT_EQ(relay.counters().refused_by.at("/user"), 2u);
}

TEST(CanRelay, HardwareRefusalIsCountedForTheSender) {
  FakeBus bus;
  bus.refuse_id = 0x124;
  CanRelay relay(bus, {0x123, 0x124}, {});
  const RelayVerdict v = relay.offer("/tool", frame(0x124));
  EXPECT_EQ(v.kind, Kind::kRefused);
  EXPECT_EQ(v.why, "malformed frame");
  EXPECT_TRUE(bus.sent.empty());
  EXPECT_EQ(relay.counters().refused_by.at("/tool"), 1u);
  EXPECT_EQ(relay.counters().sent, 0u);
}

TEST(CanRelay, BoundPerCycleOnUserFrames) {
  FakeBus bus;
  CanRelayOptions options;
  options.max_sent_per_cycle = 3;
  CanRelay relay(bus, {0x123}, options);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(relay.offer("/user", frame(0x123)).kind, Kind::kSent);
  EXPECT_EQ(relay.offer("/user", frame(0x123)).kind, Kind::kOverCycleBound);
  // A refused frame does not use up the bound; a dropped one is not refused.
  EXPECT_EQ(relay.counters().dropped, 1u);
  EXPECT_EQ(relay.counters().refused, 0u);
  relay.cycle();
  EXPECT_EQ(relay.offer("/user", frame(0x123)).kind, Kind::kSent);
  EXPECT_EQ(bus.sent.size(), 4u);
}

TEST(CanRelay, RefusalsDoNotUseUpTheBound) {
  FakeBus bus;
  CanRelayOptions options;
  options.max_sent_per_cycle = 1;
  CanRelay relay(bus, {0x123}, options);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(relay.offer("/user", frame(0x7E5)).kind, Kind::kRefused);
  EXPECT_EQ(relay.offer("/user", frame(0x123)).kind, Kind::kSent);
}

TEST(CanRelay, MutedDropsEverything) {
  FakeBus bus;
  CanRelay relay(bus, {0x123}, {});
  relay.setMuted(true);
  EXPECT_TRUE(relay.muted());
  EXPECT_EQ(relay.offer("/user", frame(0x123)).kind, Kind::kMuted);
  EXPECT_EQ(relay.offer("/user", frame(0x201)).kind, Kind::kMuted);  // not even looked at
  EXPECT_TRUE(bus.sent.empty());
  EXPECT_EQ(relay.counters().dropped, 2u);
  EXPECT_EQ(relay.counters().refused, 0u);
  relay.setMuted(false);
  EXPECT_EQ(relay.offer("/user", frame(0x123)).kind, Kind::kSent);
}

TEST(CanRelay, BusFramesBoundedPerCycle) {
  FakeBus bus;
  CanRelayOptions options;
  options.max_received_per_cycle = 4;
  CanRelay relay(bus, {}, options);
  for (uint8_t i = 0; i < 10; ++i) bus.incoming.push_back(frame(0x322, i));
  const auto first = relay.cycle();
  ASSERT_EQ(first.size(), 4u);
  for (uint8_t i = 0; i < 4; ++i) EXPECT_EQ(first[i].data[0], i);  // the oldest, in order
  EXPECT_EQ(relay.counters().received, 4u);
  EXPECT_EQ(relay.counters().received_dropped, 6u);  // the rest of that cycle's frames are dropped, not kept
  EXPECT_TRUE(relay.cycle().empty());
  bus.incoming.push_back(frame(0x322));
  EXPECT_EQ(relay.cycle().size(), 1u);
  EXPECT_EQ(relay.counters().received, 5u);
}

TEST(CanRelay, SendersCountedOneByOneUpToABound) {
  FakeBus bus;
  CanRelay relay(bus, {}, {});
  const size_t senders = CanRelay::kMaxSenders + 5;
  for (size_t i = 0; i < senders; ++i) relay.offer("/node" + std::to_string(i), frame(0x300));
  const auto& by = relay.counters().refused_by;
  EXPECT_EQ(by.size(), CanRelay::kMaxSenders + 1);
  EXPECT_EQ(by.at("(other senders)"), 5u);
  EXPECT_EQ(relay.counters().refused, senders);
  // A sender counted one by one stays so.
  EXPECT_EQ(relay.offer("/node0", frame(0x300)).refused_from_sender, 2u);
}

TEST(CanRelay, BoundsBelowOneAreRefused) {
  FakeBus bus;
  CanRelayOptions options;
  options.max_sent_per_cycle = 0;
  EXPECT_THROW(CanRelay(bus, {}, options), ConfigError);
  options = CanRelayOptions();
  options.max_received_per_cycle = 0;
  EXPECT_THROW(CanRelay(bus, {}, options), ConfigError);
}

}  // namespace
}  // namespace thorvald_base
