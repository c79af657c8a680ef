// Host devices against the device simulator on the virtual bus, stepped on a fake clock.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "rig.h"
#include "thorvald_base/relay_allow_list.h"
#include "thorvald_can_devices/battery_protocol.h"
#include "thorvald_can_devices/canopen_protocol.h"
#include "thorvald_can_devices/drive_scaling.h"
#include "thorvald_can_devices/thorvald_drive_protocol.h"

using namespace thorvald_can_devices;

namespace {

bool allOnline(Rig& rig) {
  for (auto& d : rig.drives) {
    const auto s = d->status();
    if (!s.online || s.fault) return false;
  }
  return true;
}

TEST(ThorvaldDrive, StartsDrivesAndFollowsCommands) {
  Rig rig("robots/4wd4ws.yaml");
  EXPECT_EQ(rig.hw.notAnswering().size(), 6u);  // nothing answered at t0: the simulator had not run yet
  rig.run(0.3);
  ASSERT_TRUE(allOnline(rig)) << rig.drives[0]->status().text;
  for (auto& c : rig.commands) c = {5.0, 0.5};
  rig.spied();
  rig.run(2.0);
  for (size_t i = 0; i < rig.drives.size(); ++i) {
    const auto fb = rig.drives[i]->feedback();
    ASSERT_TRUE(fb.valid);
    EXPECT_NEAR(fb.wheel_speed_radps, 5.0, 0.01) << i;  // 1 rpm resolution = 0.0025 rad/s
    EXPECT_NEAR(fb.steering_rad, 0.5, 0.005) << i;      // command resolution str_lim/1000 = 0.003 rad
  }
  // The frames on the bus: 5 rad/s -> 668 of 1000; 0.5 rad -> 162 of 1000 (0.5 / 3.078 * 1000 = 162.4).
  int32_t last_seq = 0;
  int commands = 0;
  for (const auto& f : rig.spied()) {
    if (f.stdId() == 0x201) {
      const auto c = decodeCommand(f);
      ASSERT_TRUE(c);
      EXPECT_EQ(c->propulsion, 668);
      if (commands++ > 0) {
        EXPECT_EQ(c->sequence, last_seq + 1);
      }
      last_seq = c->sequence;
    } else if (f.stdId() == 0x501) {
      EXPECT_EQ(decodeSteering(f)->position, 162);
      EXPECT_EQ(decodeSteering(f)->max_speed_rpm, 1637);  // 4 rad/s * 42.857 * 30/pi
    }
  }
  EXPECT_EQ(commands, 100);  // one per 20 ms cycle
}

TEST(ThorvaldDrive, TwoChannelPairOnOneNode) {
  Rig rig("robots/diff.yaml");
  ASSERT_EQ(rig.drives.size(), 2u);
  rig.run(0.3);
  ASSERT_TRUE(allOnline(rig));
  rig.commands[0] = {3.0, 0.0};
  rig.commands[1] = {-2.0, 0.0};
  rig.spied();
  rig.run(2.0);
  EXPECT_NEAR(rig.drives[0]->feedback().wheel_speed_radps, 3.0, 0.01);
  EXPECT_NEAR(rig.drives[1]->feedback().wheel_speed_radps, -2.0, 0.01);
  EXPECT_NEAR(rig.sim.thorvaldDrives()[0].wheelSpeed(1), -2.0, 0.01);
  // Wheel position integrates the speed: 2 s at about 3 rad/s less the 0.4 s ramp (7.5 rad/s^2).
  EXPECT_NEAR(rig.drives[0]->feedback().wheel_position_rad, 3.0 * 2.0 - 0.5 * 3.0 * 0.4, 0.15);
  bool saw_channel2 = false;
  for (const auto& f : rig.spied()) {
    if (f.stdId() == 0x501) {
      // -2 rad/s * 42 * 30/pi * 1000/3000 = -267.4
      EXPECT_EQ(decodeSteering(f)->position, -267);
      saw_channel2 = true;
    }
  }
  EXPECT_TRUE(saw_channel2);
}

TEST(ThorvaldDrive, SilentNodeIsLostWithinItsFeedbackTimeoutAndRecoversAfterReboot) {
  Rig rig("robots/4wd4ws.yaml");
  rig.run(0.3);
  ASSERT_TRUE(allOnline(rig));
  ASSERT_TRUE(rig.inject("drive1", "silent", true));
  const double silent_at = rig.t;
  double lost_at = -1;
  for (int i = 0; i < 200 && lost_at < 0; ++i) {
    rig.cycle();
    if (!rig.drives[1]->status().online) lost_at = rig.t;
  }
  ASSERT_GT(lost_at, 0);
  // The last feedback came at most one period (20 ms) before the silence; lost 60 ms after it, within a cycle.
  EXPECT_GT(lost_at - silent_at, 0.06 - 0.02 - 1e-9);
  EXPECT_LE(lost_at - silent_at, 0.06 + 0.02 + 1e-9);
  EXPECT_NE(rig.drives[1]->status().text.find("no feedback for"), std::string::npos) << rig.drives[1]->status().text;
  EXPECT_TRUE(rig.drives[0]->status().online);
  ASSERT_TRUE(rig.inject("drive1", "silent", false));
  rig.run(1.0);
  EXPECT_TRUE(rig.drives[1]->status().online) << rig.drives[1]->status().text;
}

TEST(ThorvaldDrive, HeartbeatsAloneDoNotKeepADrive) {
  Rig rig("robots/4wd4ws.yaml");
  rig.run(0.3);
  ASSERT_TRUE(allOnline(rig));
  // The drive dies, but something keeps sending its "operational" heartbeat.
  ASSERT_TRUE(rig.inject("drive2", "silent", true));
  double lost_at = -1;
  const double silent_at = rig.t;
  for (int i = 0; i < 100 && lost_at < 0; ++i) {
    rig.spy->send(encodeHeartbeat(rig.config.drives[2].node, kHeartbeatOperational));
    rig.cycle();
    if (!rig.drives[2]->status().online) lost_at = rig.t;
  }
  ASSERT_GT(lost_at, 0.0) << "a spoofed heartbeat kept a silent drive online";
  EXPECT_LE(lost_at - silent_at, 0.1 + 1e-9);
}

TEST(ThorvaldDrive, FirstFeedbackMayTakeHalfASecondThenItIsLost) {
  // drive2 answers nothing but its heartbeat says operational: it is given 0.5 s for its first feedback (a drive or a
  // loaded host may take a few periods to start), not the 60 ms that a drive already feeding back gets.
  Rig rig("robots/4wd4ws.yaml");
  ASSERT_TRUE(rig.inject("drive2", "silent", true));
  double lost_at = -1;
  for (int i = 0; i < 60 && lost_at < 0; ++i) {
    rig.spy->send(encodeHeartbeat(rig.config.drives[2].node, kHeartbeatOperational));
    rig.cycle();
    if (i == 15) {
      EXPECT_TRUE(rig.drives[2]->status().online) << rig.drives[2]->status().text;  // 0.32 s in
    }
    if (i > 15 && !rig.drives[2]->status().online) lost_at = i * 0.02;
  }
  ASSERT_GT(lost_at, 0.0) << "a drive that never fed back stayed online";
  EXPECT_LE(lost_at, 0.5 + 0.06);
  EXPECT_NE(rig.drives[2]->status().text.find("no feedback for"), std::string::npos) << rig.drives[2]->status().text;
}

TEST(ThorvaldDrive, StallIsAFaultUntilClearedAfterTheCauseIsGone) {
  Rig rig("robots/4wd4ws.yaml");
  rig.run(0.3);
  ASSERT_TRUE(rig.inject("drive2", "stall", true));
  rig.run(0.1);
  auto s = rig.drives[2]->status();
  EXPECT_TRUE(s.fault);
  EXPECT_EQ(s.text, "stall");
  rig.drives[2]->clearFault();
  rig.run(0.1);
  EXPECT_TRUE(rig.drives[2]->status().fault);  // still stalled
  ASSERT_TRUE(rig.inject("drive2", "stall", false));
  rig.drives[2]->clearFault();
  rig.run(0.1);
  EXPECT_FALSE(rig.drives[2]->status().fault) << rig.drives[2]->status().text;
  ASSERT_TRUE(rig.inject("drive3", "encoder", true));
  rig.run(0.1);
  EXPECT_EQ(rig.drives[3]->status().text, "propulsion encoder fault");
}

TEST(ThorvaldDrive, HomingRunsToTheIndexAndReturnsToDriveMode) {
  Rig rig("robots/4wd4ws.yaml");
  rig.run(0.3);
  rig.commands[0] = {0.0, 1.0};
  rig.run(0.5);
  ASSERT_NEAR(rig.drives[0]->feedback().steering_rad, 1.0, 0.005);
  rig.commands[0] = {0.0, 1.0};  // base_driver keeps sending its targets while homing
  ASSERT_TRUE(rig.drives[0]->startHoming());
  rig.cycle();
  EXPECT_TRUE(rig.drives[0]->status().homing);
  rig.run(1.0);  // 1 rad at 2 rad/s
  EXPECT_FALSE(rig.drives[0]->status().homing);
  EXPECT_FALSE(rig.drives[0]->status().fault);
}

TEST(ThorvaldDrive, MalformedFramesAreCountedAndIgnored) {
  Rig rig("robots/4wd4ws.yaml");
  rig.run(0.3);
  rig.commands[0] = {2.0, 0.0};
  rig.run(1.0);
  const double speed = rig.drives[0]->feedback().wheel_speed_radps;
  const unsigned long before = rig.hw.malformedFrames();
  rig.spy->send(makeFrame(0x181, {0x10, 0x27, 0, 0}));        // feedback with 4 bytes
  rig.spy->send(makeFrame(0x481, {0, 0, 0, 7, 0, 0, 0, 0}));  // unknown info type
  rig.spy->send(makeFrame(0x381, {0xFF, 0, 0, 0, 0, 0, 0}));  // status with 7 bytes
  rig.hw.poll(rig.t);
  EXPECT_EQ(rig.hw.malformedFrames(), before + 3);
  EXPECT_DOUBLE_EQ(rig.drives[0]->feedback().wheel_speed_radps, speed);
  EXPECT_FALSE(rig.drives[0]->status().fault);
}

TEST(ThorvaldBattery, ReadingAlarmAndSilence) {
  Rig rig("robots/4wd4ws.yaml");
  rig.run(0.5);
  ASSERT_EQ(rig.batteries.size(), 2u);
  auto r = rig.batteries[1]->reading();
  EXPECT_TRUE(r.online && r.present);
  EXPECT_DOUBLE_EQ(r.voltage_v, 51.2);
  EXPECT_DOUBLE_EQ(r.current_a, -3.5);
  EXPECT_DOUBLE_EQ(r.charge_pct, 87);
  EXPECT_DOUBLE_EQ(r.health_pct, 96);
  EXPECT_EQ(r.cycles, 132);
  ASSERT_EQ(r.temperatures_c.size(), 7u);
  EXPECT_DOUBLE_EQ(r.temperatures_c[0], 24);
  EXPECT_DOUBLE_EQ(r.temperatures_c[6], 30);
  EXPECT_TRUE(r.charging_enabled && r.discharging_enabled);
  ASSERT_TRUE(rig.inject("bat1", "alarm", true));
  rig.run(0.3);
  EXPECT_EQ(rig.batteries[1]->reading().alarms, battery_alarms::kOverTemperature);
  EXPECT_EQ(rig.batteries[0]->reading().alarms, 0);
  ASSERT_TRUE(rig.inject("bat0", "silent", true));
  rig.run(2.5);
  EXPECT_FALSE(rig.batteries[0]->reading().online);
  EXPECT_FALSE(rig.inject("bat7", "alarm", true));
  EXPECT_FALSE(rig.inject("bat0", "stall", true));
}

TEST(Cia402Drive, ConfiguresStartsEnablesAndFollows) {
  Rig rig("robots/mixed.yaml");
  rig.run(1.0);
  ASSERT_TRUE(allOnline(rig)) << rig.drives[0]->status().text;
  EXPECT_EQ(rig.sim.cia402Axes()[0].mode(), cia402::kModeProfileVelocity);
  EXPECT_EQ(rig.sim.cia402Axes()[1].mode(), cia402::kModeProfilePosition);
  EXPECT_EQ(rig.sim.cia402Axes()[1].node(), 75);
  for (auto& c : rig.commands) c = {4.0, -0.7};
  rig.spied();
  rig.run(2.0);
  for (size_t i = 0; i < rig.drives.size(); ++i) {
    EXPECT_NEAR(rig.drives[i]->feedback().wheel_speed_radps, 4.0, 0.01) << i;
    EXPECT_NEAR(rig.drives[i]->feedback().steering_rad, -0.7, 0.005) << i;
  }
  // 4 rad/s = 4 * 42 * 4096 / 2pi = 109518.9 -> 109519 increments/s in the RPDO of node 11.
  bool seen = false;
  for (const auto& f : rig.spied()) {
    if (f.stdId() == 0x20B) {
      const auto p = decodeRpdo1(f);
      ASSERT_TRUE(p);
      EXPECT_EQ(p->controlword, cia402::kCwEnableOperation);
      EXPECT_EQ(p->target, 109519);
      seen = true;
    }
  }
  EXPECT_TRUE(seen);
}

TEST(Cia402Drive, FaultResetAndHostHeartbeatLoss) {
  Rig rig("robots/mixed.yaml");
  rig.run(1.0);
  ASSERT_TRUE(rig.inject("drive3", "stall", true));
  rig.run(0.1);
  auto s = rig.drives[3]->status();
  EXPECT_TRUE(s.fault);
  EXPECT_NE(s.text.find("EMCY 0x7121"), std::string::npos) << s.text;
  ASSERT_TRUE(rig.inject("drive3", "stall", false));
  rig.drives[3]->clearFault();
  rig.run(0.5);
  EXPECT_TRUE(rig.drives[3]->status().online && !rig.drives[3]->status().fault) << rig.drives[3]->status().text;
  // The host stops (no heartbeat 0x77F): the drives stop by themselves after 500 ms.
  rig.run(0.7, false);
  EXPECT_EQ(rig.sim.cia402Axes()[0].state(), Cia402State::kFault);
  EXPECT_DOUBLE_EQ(rig.sim.cia402Axes()[0].velocity(), 0.0);
}

TEST(Cia402Drive, SilentDriveIsLostWithin100ms) {
  Rig rig("robots/mixed.yaml");
  rig.run(1.0);
  ASSERT_TRUE(allOnline(rig));
  ASSERT_TRUE(rig.inject("drive0", "silent", true));
  const double silent_at = rig.t;
  double lost_at = -1;
  for (int i = 0; i < 200 && lost_at < 0; ++i) {
    rig.cycle();
    if (!rig.drives[0]->status().online) lost_at = rig.t;
  }
  ASSERT_GT(lost_at, 0.0);
  EXPECT_LE(lost_at - silent_at, 0.1 + 1e-9) << rig.drives[0]->status().text;
  EXPECT_NE(rig.drives[0]->status().text.find("no PDO answer"), std::string::npos) << rig.drives[0]->status().text;
  EXPECT_EQ(rig.drives[0]->status().text.find("operation enabled"), std::string::npos) << rig.drives[0]->status().text;
  EXPECT_TRUE(rig.drives[1]->status().online);
}

TEST(CanBase, AFloodNeitherStallsThePollNorStarvesTheDrives) {
  Rig rig("robots/mixed.yaml");
  rig.run(1.0);
  ASSERT_TRUE(allOnline(rig));
  VirtualCanBus flooder(rig.bus_name);
  const CanFrame junk = makeFrame(0x321, {1, 2, 3});
  const unsigned long bound = rig.hw.options().max_frames_per_poll;
  unsigned long most_per_poll = 0;
  unsigned long heartbeats = 0;
  // 2 s of cycles with 2000 frames (100,000 frames/s) sent between two polls.
  for (int c = 0; c < 100; ++c) {
    for (int k = 0; k < 2000; ++k) flooder.send(junk);
    const unsigned long before = rig.hw.bus().status().frames_received;
    rig.cycle();
    most_per_poll = std::max(most_per_poll, rig.hw.bus().status().frames_received - before);
    ASSERT_TRUE(allOnline(rig)) << "cycle " << c;
    for (const auto& f : rig.spied())
      if (f.stdId() == 0x77F) ++heartbeats;
  }
  EXPECT_LE(most_per_poll, bound);
  EXPECT_GT(rig.hw.readBoundHits(), 50u);
  EXPECT_GE(heartbeats, 19u);  // the host heartbeat (every 100 ms) went on through the flood
  // Frames past the bound are counted: at least what the flood sent beyond the bound and the socket still held.
  EXPECT_GT(rig.hw.framesPastReadBound(), 50u * bound);
  bool reported = false;
  for (const auto& kv : rig.hw.diagnostics()) {
    if (kv.first == "CAN frames past the read bound")
      reported = kv.second == std::to_string(rig.hw.framesPastReadBound());
  }
  EXPECT_TRUE(reported);
}

TEST(CanBase, SyncGoesOutEveryCycleButNeverFasterThanItsMinimumPeriod) {
  Rig rig("robots/mixed.yaml");
  const auto syncs = [&rig] {
    int n = 0;
    for (const auto& f : rig.spied())
      if (f.stdId() == 0x080) ++n;
    return n;
  };
  syncs();
  rig.run(1.0);  // 50 host cycles of 20 ms: one SYNC each
  EXPECT_EQ(syncs(), 50);
  ASSERT_TRUE(allOnline(rig));
  // Polls as fast as frames arrive (start-up does this): 200 polls in 50 ms give one SYNC per minimum period.
  for (int k = 0; k < 200; ++k) {
    rig.t += 0.00025;
    rig.hw.poll(rig.t);
  }
  const int fast = syncs();
  EXPECT_GE(fast, static_cast<int>(0.05 / kMinSyncPeriodS) - 1);
  EXPECT_LE(fast, static_cast<int>(0.05 / kMinSyncPeriodS) + 1);
  rig.run(0.2);
  EXPECT_TRUE(allOnline(rig));  // fewer SYNCs in that burst did not make any axis look silent
}

TEST(CanBase, VirtualBusCountsTheFramesWaiting) {
  const std::string bus = "waiting" + std::to_string(::getpid());
  VirtualCanBus receiver(bus), sender(bus);
  EXPECT_EQ(receiver.framesWaiting(), 0);
  CanFrame f;
  receiver.receive(&f);  // accepts the sender's connection
  for (int k = 0; k < 37; ++k) sender.send(makeFrame(0x321, {static_cast<uint8_t>(k)}));
  receiver.receive(&f);
  EXPECT_EQ(receiver.framesWaiting(), 36);
  while (receiver.receive(&f)) {
  }
  EXPECT_EQ(receiver.framesWaiting(), 0);
}

TEST(CanBase, NamesTheDeviceOfEveryBaseIdAndKeepsThemOffTheRelayAllowList) {
  Rig rig("robots/4wd4ws.yaml");
  EXPECT_EQ(rig.hw.canIdUser(0x000), "NMT");
  EXPECT_EQ(rig.hw.canIdUser(0x080), "SYNC");
  for (uint32_t id : {0x201u, 0x181u, 0x704u}) EXPECT_NE(rig.hw.canIdUser(id), "") << std::hex << id;
  EXPECT_EQ(rig.hw.canIdUser(0x123), "");
  const auto allowed = thorvald_base::relayAllowList({{0x123, 0x7E4}, "robot.yaml", "implement_can_ids"}, rig.hw);
  EXPECT_EQ(allowed, (std::set<uint32_t>{0x123, 0x7E4}));
  try {
    thorvald_base::relayAllowList({{0x123, 0x201}, "robot.yaml", "implement_can_ids"}, rig.hw);
    FAIL() << "a drive's id was allowed";
  } catch (const thorvald_base::ConfigError& e) {
    EXPECT_EQ(e.where(), "implement_can_ids[1]");
    EXPECT_NE(e.problem().find("0x201 is used by the base (" + rig.hw.canIdUser(0x201) + ")"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(thorvald_base::relayAllowList({{0x080}, "base_driver", "~relay_allowed_ids"}, rig.hw),
               thorvald_base::ConfigError);
  EXPECT_THROW(thorvald_base::relayAllowList({{0x800}, "base_driver", "~relay_allowed_ids"}, rig.hw),
               thorvald_base::ConfigError);
}

TEST(CanBase, RelayRefusesBaseIdsAndPassesOthers) {
  Rig rig("robots/4wd4ws.yaml");
  rig.run(0.3);
  std::string why;
  thorvald_base::CanFrameData f;
  f.length = 2;
  for (uint32_t id : {0x000u, 0x080u, 0x201u, 0x501u, 0x181u, 0x704u, 0x3C1u, 0x3E0u, 0x604u}) {
    f.id = id;
    EXPECT_FALSE(rig.hw.sendRelayFrame(f, &why)) << std::hex << id;
  }
  f.id = 0x201;
  rig.hw.sendRelayFrame(f, &why);
  EXPECT_EQ(why, "id 0x201 belongs to a base device");
  f.id = 0x900;
  EXPECT_FALSE(rig.hw.sendRelayFrame(f, &why));
  f.id = 0x123;
  f.length = 9;
  EXPECT_FALSE(rig.hw.sendRelayFrame(f, &why));
  f.length = 2;
  f.data[0] = 0xAB;
  rig.spied();
  ASSERT_TRUE(rig.hw.sendRelayFrame(f, &why)) << why;
  bool seen = false;
  for (const auto& g : rig.spied()) seen = seen || (g.id == 0x123 && g.data[0] == 0xAB);
  EXPECT_TRUE(seen);
  rig.hw.takeRelayFrames();
  rig.spy->send(makeFrame(0x321, {1, 2, 3}));
  rig.cycle();
  const auto relayed = rig.hw.takeRelayFrames();
  ASSERT_EQ(relayed.size(), 1u);
  EXPECT_EQ(relayed[0].id, 0x321u);
  EXPECT_EQ(relayed[0].length, 3);
}

TEST(CanBase, BusOffFaultsEveryDriveUntilTheControllerRestarts) {
  Rig rig("robots/4wd4ws.yaml");
  rig.run(0.3);
  ASSERT_TRUE(rig.inject("bus", "bus_off", true));
  rig.cycle();
  EXPECT_FALSE(rig.hw.busOk());
  for (auto& d : rig.drives) EXPECT_EQ(d->status().text, "bus off");
  ASSERT_TRUE(rig.inject("bus", "bus_off", false));
  rig.cycle();
  EXPECT_TRUE(rig.hw.busOk());
  EXPECT_TRUE(allOnline(rig));
}

TEST(CanBase, StartupReportsDevicesThatDoNotAnswer) {
  auto config = thorvald_base::loadRobotConfigFile("robots/diff.yaml");
  CanBaseHardware hw(CanBaseOptions{0.1, "", 1000});
  hw.initializeOnBus(config, std::make_unique<VirtualCanBus>("nobody" + std::to_string(::getpid())));
  ASSERT_EQ(hw.notAnswering().size(), 2u);
  EXPECT_EQ(hw.notAnswering()[0], "drive0+drive1 (thorvald node 1)");
  EXPECT_EQ(hw.notAnswering()[1], "bat0 (battery id 2)");
  const auto drives = hw.takeDrives();
  EXPECT_FALSE(drives[0]->status().online);
  EXPECT_EQ(drives[0]->status().text, "never answered");
}

TEST(CanBase, RefusesCollidingIds) {
  auto config = thorvald_base::loadRobotConfigFile("robots/4wd4ws.yaml");
  config.drives[3].node = 2;  // two type-0 drives on node 2
  CanBaseHardware hw(CanBaseOptions{0.0, "", 1000});
  EXPECT_THROW(hw.initializeOnBus(config, std::make_unique<VirtualCanBus>("clash" + std::to_string(::getpid()))),
               thorvald_base::ConfigError);
}

}  // namespace
