// Byte-exact encode/decode of every frame type against frames computed by hand from the README layouts.
#include <gtest/gtest.h>

#include <cmath>

#include "thorvald_can_devices/battery_protocol.h"
#include "thorvald_can_devices/bus_error.h"
#include "thorvald_can_devices/candump_log.h"
#include "thorvald_can_devices/canopen_protocol.h"
#include "thorvald_can_devices/drive_scaling.h"
#include "thorvald_can_devices/thorvald_drive_protocol.h"

using namespace thorvald_can_devices;

namespace {

CanFrame F(uint32_t id, std::initializer_list<uint8_t> b) { return makeFrame(id, b); }

thorvald_base::DriveConfig figure5Drive() {
  thorvald_base::DriveConfig d;
  d.node = 1;
  d.r_wheel = 0.2;
  d.prp_gr_rt = 42;
  d.prp_enc_ppr = 1024;
  d.prp_max_rpm = 3000;
  d.str_gr_rt = 42.8571429;
  d.str_enc_ppr = 1024;
  d.str_lim = 3.078027759;
  d.str_sim_v = 4;
  return d;
}

TEST(ThorvaldFrames, CommandIsSequenceThenPropulsionLittleEndian) {
  EXPECT_EQ(encodeCommand(1, {7, 500}), F(0x201, {0x07, 0, 0, 0, 0xF4, 0x01, 0, 0}));
  // Negative full scale and a wrapped sequence counter.
  EXPECT_EQ(encodeCommand(127, {-1, -1000}), F(0x27F, {0xFF, 0xFF, 0xFF, 0xFF, 0x18, 0xFC, 0xFF, 0xFF}));
  const auto c = decodeCommand(F(0x27F, {0xFF, 0xFF, 0xFF, 0xFF, 0x18, 0xFC, 0xFF, 0xFF}));
  ASSERT_TRUE(c);
  EXPECT_EQ(c->sequence, -1);
  EXPECT_EQ(c->propulsion, -1000);
}

TEST(ThorvaldFrames, SetupModeSteering) {
  EXPECT_EQ(encodeSetup(3, {thorvald_setup::kCommandTimeoutMs, 500}), F(0x303, {2, 0, 0, 0, 0xF4, 0x01, 0, 0}));
  EXPECT_EQ(encodeMode(3, ThorvaldMode::kHomeSteering), F(0x403, {1, 0, 0, 0}));
  EXPECT_EQ(encodeSteering(3, {1637, -1000}), F(0x503, {0x65, 0x06, 0, 0, 0x18, 0xFC, 0xFF, 0xFF}));
  EXPECT_EQ(*decodeMode(F(0x403, {2, 0, 0, 0})), ThorvaldMode::kDecoupled);
  EXPECT_FALSE(decodeMode(F(0x403, {3, 0, 0, 0})));  // unknown mode
  EXPECT_FALSE(decodeMode(F(0x403, {1})));           // wrong length
  const auto s = decodeSteering(F(0x503, {0x65, 0x06, 0, 0, 0x18, 0xFC, 0xFF, 0xFF}));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->max_speed_rpm, 1637);
  EXPECT_EQ(s->position, -1000);
}

TEST(ThorvaldFrames, FeedbackPowerStatus) {
  // rpm -3000 = 0xF448, steering rpm 120 = 0x0078, count -123456 = 0xFFFE1DC0.
  const CanFrame fb = F(0x182, {0x48, 0xF4, 0x78, 0x00, 0xC0, 0x1D, 0xFE, 0xFF});
  EXPECT_EQ(encodeFeedback(2, {-3000, 120, -123456}), fb);
  const auto d = decodeFeedback(fb);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->propulsion_rpm, -3000);
  EXPECT_EQ(d->steering_rpm, 120);
  EXPECT_EQ(d->steering_count, -123456);
  ThorvaldPower p;
  p.current_da[0] = 25;
  p.current_da[1] = -3;
  p.power_permille[0] = 500;
  p.power_permille[1] = -500;
  EXPECT_EQ(encodePower(2, p), F(0x282, {25, 0, 0xFD, 0xFF, 0xF4, 0x01, 0x0C, 0xFE}));
  ThorvaldStatus st;
  st.flags = thorvald_flags::kStall | thorvald_flags::kControllerOk;
  st.max_temperature_c = -5;
  st.battery_current_da = -12;
  st.battery_voltage_dv = 512;
  EXPECT_EQ(encodeStatus(2, st), F(0x382, {0x09, 0xFB, 0xF4, 0xFF, 0x00, 0x02}));
  const auto s = decodeStatus(F(0x382, {0x09, 0xFB, 0xF4, 0xFF, 0x00, 0x02}));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->max_temperature_c, -5);
  EXPECT_EQ(s->battery_voltage_dv, 512);
  EXPECT_EQ(describeFlags(s->flags), "stall");
  EXPECT_EQ(describeFlags(0x00), "controller not ok");
  EXPECT_EQ(describeFlags(0x81), "propulsion encoder fault");
  EXPECT_FALSE(decodeStatus(F(0x382, {0x01, 0, 0, 0, 0, 0, 0, 0})));  // 8 bytes: wrong length
}

TEST(ThorvaldFrames, InfoTypesAndUnknownType) {
  ThorvaldInfo h;
  h.type = 1;
  h.home_direction = -1;
  h.home_speed_rpm = 818;
  h.home_count = 4096;
  EXPECT_EQ(encodeInfo(1, h), F(0x481, {0xFF, 0x32, 0x03, 1, 0x00, 0x10, 0, 0}));
  ThorvaldInfo v;
  v.type = 2;
  v.controller_type = 1;
  v.script_version = 0x0203;
  EXPECT_EQ(encodeInfo(1, v), F(0x481, {1, 0x03, 0x02, 2, 0, 0, 0, 0}));
  ThorvaldInfo e;
  e.type = 3;
  e.encoder_ppr = 1024;
  EXPECT_EQ(encodeInfo(1, e), F(0x481, {0, 0, 0, 3, 0x00, 0x04, 0, 0}));
  EXPECT_EQ(decodeInfo(F(0x481, {0, 0, 0, 3, 0x00, 0x04, 0, 0}))->encoder_ppr, 1024);
  EXPECT_FALSE(decodeInfo(F(0x481, {0, 0, 0, 4, 0, 0, 0, 0})));  // unknown message type byte
  EXPECT_FALSE(decodeInfo(F(0x481, {2, 0, 0, 1, 0, 0, 0, 0})));  // homing direction 2
  EXPECT_FALSE(decodeInfo(F(0x481, {0, 0, 0, 3})));              // short
}

TEST(ThorvaldFrames, HeartbeatAndForeignIds) {
  EXPECT_EQ(encodeHeartbeat(5, kHeartbeatOperational), F(0x705, {5}));
  EXPECT_EQ(*decodeHeartbeat(F(0x705, {0x7F})), kHeartbeatPreOperational);
  EXPECT_FALSE(decodeHeartbeat(F(0x705, {0x06})));
  EXPECT_FALSE(decodeHeartbeat(F(0x705, {5, 0})));
  EXPECT_FALSE(decodeCommand(F(0x200, {0, 0, 0, 0, 0, 0, 0, 0})));  // node 0 is not a drive
  EXPECT_FALSE(decodeFeedback(F(0x201, {0, 0, 0, 0, 0, 0, 0, 0})));
  CanFrame ext = encodeCommand(1, {1, 1});
  ext.id |= kCanEffFlag;
  EXPECT_FALSE(decodeCommand(ext));
}

TEST(Scaling, PaperFigure5Drive) {
  const auto d = figure5Drive();
  // 1 m/s on a 0.2 m wheel: 5 rad/s * 42 * 30/pi = 2005.352 rpm -> 668.45 of 1000.
  EXPECT_EQ(ThorvaldScaling::propulsionCommand(5.0, d), 668);
  EXPECT_EQ(ThorvaldScaling::propulsionCommand(-5.0, d), -668);
  EXPECT_EQ(ThorvaldScaling::propulsionCommand(100.0, d), 1000);  // clamped
  EXPECT_EQ(ThorvaldScaling::propulsionCommand(std::nan(""), d), 0);
  EXPECT_EQ(ThorvaldScaling::steeringCommand(d.str_lim / 2, d), 500);
  EXPECT_EQ(ThorvaldScaling::steeringCommand(-4.0, d), -1000);
  // 2005 rpm back to wheel speed: 2005 / 42 * pi / 30 = 4.99912 rad/s.
  EXPECT_NEAR(ThorvaldScaling::wheelSpeedFromRpm(2005, d), 4.99912, 1e-5);
  // A quarter steering turn: 1024 * 4 * 42.857 / 4 = 43885.7 counts.
  EXPECT_EQ(ThorvaldScaling::countFromSteering(M_PI / 2, d), 43886);
  EXPECT_NEAR(ThorvaldScaling::steeringFromCount(43886, d), M_PI / 2, 1e-4);
}

TEST(BatteryFrames, AllThreeByteExact) {
  BatteryStateFrame s;
  s.status = 1;
  s.fets = 3;
  s.voltage_cv = 5120;
  s.alarms = battery_alarms::kOverTemperature;
  s.temperature_c[0] = 24;
  s.temperature_c[1] = -10;
  EXPECT_EQ(encodeBatteryState(2, s), F(0x3C2, {1, 3, 0x00, 0x14, 0x10, 0x00, 24, 0xF6}));
  BatteryCurrentFrame c;
  c.temperature_c[0] = 26;
  c.temperature_c[1] = 27;
  c.temperature_c[2] = 28;
  c.temperature_c[3] = 29;
  c.temperature_c[4] = -1;
  c.current_ca = -350;
  EXPECT_EQ(encodeBatteryCurrent(2, c), F(0x3D2, {26, 27, 28, 29, 0xA2, 0xFE, 0xFF}));
  EXPECT_EQ(decodeBatteryCurrent(F(0x3D2, {26, 27, 28, 29, 0xA2, 0xFE, 0xFF}))->current_ca, -350);
  EXPECT_EQ(encodeBatteryCharge(2, {87, 96, 132}), F(0x3E2, {87, 96, 132, 0}));
  EXPECT_FALSE(decodeBatteryCharge(F(0x3E2, {101, 96, 0, 0})));  // 101 %
  EXPECT_FALSE(decodeBatteryState(F(0x3C2, {1, 3, 0, 0})));      // short
  EXPECT_EQ(decodeBatteryState(F(0x3CF, {1, 3, 0x00, 0x14, 0x10, 0x00, 24, 0xF6}))->temperature_c[1], -10);
}

TEST(CanopenFrames, NmtSyncEmcy) {
  EXPECT_EQ(encodeNmt(NmtCommand::kStart, 5), F(0x000, {0x01, 0x05}));
  EXPECT_EQ(encodeNmt(NmtCommand::kResetCommunication, 0), F(0x000, {0x82, 0x00}));
  EXPECT_FALSE(decodeNmt(F(0x000, {0x03, 0x05})));
  EXPECT_EQ(encodeSync(), F(0x080, {}));
  EXPECT_EQ(encodeEmergency(5, {0x8130, 0x11}), F(0x085, {0x30, 0x81, 0x11, 0, 0, 0, 0, 0}));
  EXPECT_EQ(decodeEmergency(F(0x085, {0x30, 0x81, 0x11, 0, 0, 0, 0, 0}))->error_code, 0x8130);
}

TEST(CanopenFrames, SdoExpedited) {
  SdoMessage w;
  w.kind = SdoMessage::Kind::kWriteRequest;
  w.index = 0x1017;
  w.value = 100;
  w.size = 2;
  EXPECT_EQ(encodeSdoRequest(5, w), F(0x605, {0x2B, 0x17, 0x10, 0x00, 0x64, 0x00, 0, 0}));
  w.index = 0x6060;
  w.value = 3;
  w.size = 1;
  EXPECT_EQ(encodeSdoRequest(5, w), F(0x605, {0x2F, 0x60, 0x60, 0x00, 0x03, 0, 0, 0}));
  w.index = 0x1016;
  w.subindex = 1;
  w.value = 0x007F01F4;
  w.size = 4;
  EXPECT_EQ(encodeSdoRequest(5, w), F(0x605, {0x23, 0x16, 0x10, 0x01, 0xF4, 0x01, 0x7F, 0x00}));
  const auto ack = decodeSdo(F(0x585, {0x60, 0x16, 0x10, 0x01, 0, 0, 0, 0}));
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->kind, SdoMessage::Kind::kWriteAck);
  EXPECT_EQ(ack->index, 0x1016);
  const auto abort = decodeSdo(F(0x585, {0x80, 0x60, 0x60, 0x00, 0x00, 0x00, 0x02, 0x06}));
  ASSERT_TRUE(abort);
  EXPECT_EQ(abort->kind, SdoMessage::Kind::kAbort);
  EXPECT_EQ(abort->value, 0x06020000u);
  const auto read = decodeSdo(F(0x585, {0x4B, 0x41, 0x60, 0x00, 0x27, 0x00, 0, 0}));
  ASSERT_TRUE(read);
  EXPECT_EQ(read->size, 2);
  EXPECT_EQ(read->value, 0x27u);
  EXPECT_FALSE(decodeSdo(F(0x585, {0x41, 0x41, 0x60, 0x00, 0, 0, 0, 0})));  // segmented: refused
  EXPECT_FALSE(decodeSdo(F(0x585, {0x60, 0x41, 0x60})));                    // short
}

TEST(CanopenFrames, Cia402PdosAndStateMachine) {
  EXPECT_EQ(encodeRpdo1(5, {0x0F, -10000}), F(0x205, {0x0F, 0x00, 0xF0, 0xD8, 0xFF, 0xFF}));
  EXPECT_EQ(encodeTpdo1(5, {0x1627, 10000}), F(0x185, {0x27, 0x16, 0x10, 0x27, 0x00, 0x00}));
  EXPECT_EQ(encodeTpdo2(5, {-2, 3}), F(0x285, {0xFE, 0xFF, 0xFF, 0xFF, 0x03}));
  EXPECT_EQ(stateOf(0x0250), Cia402State::kSwitchOnDisabled);
  EXPECT_EQ(stateOf(0x0231), Cia402State::kReadyToSwitchOn);
  EXPECT_EQ(stateOf(0x0233), Cia402State::kSwitchedOn);
  EXPECT_EQ(stateOf(0x1637), Cia402State::kOperationEnabled);
  EXPECT_EQ(stateOf(0x0217), Cia402State::kQuickStopActive);
  EXPECT_EQ(stateOf(0x0218), Cia402State::kFault);
  // The host's walk: 0x06, 0x07, 0x0F take a drive from switch on disabled to operation enabled.
  Cia402State s = Cia402State::kSwitchOnDisabled;
  for (int i = 0; i < 3; ++i) s = nextState(s, controlwordTowardsOperation(s));
  EXPECT_EQ(s, Cia402State::kOperationEnabled);
  EXPECT_EQ(nextState(Cia402State::kOperationEnabled, cia402::kCwQuickStop), Cia402State::kQuickStopActive);
  EXPECT_EQ(nextState(Cia402State::kFault, cia402::kCwEnableOperation), Cia402State::kFault);
}

TEST(BusErrors, DecodesSocketCanErrorFrames) {
  const auto off = decodeBusError(makeBusOffFrame());
  EXPECT_TRUE(off.valid && off.bus_off);
  EXPECT_EQ(off.text, "bus-off");
  CanFrame arb;
  arb.id = kCanErrorFlag | kErrLostArbitration | kErrController;
  arb.length = 8;
  arb.data[0] = 12;
  arb.data[1] = kCtrlTxPassive;
  const auto r = decodeBusError(arb);
  EXPECT_TRUE(r.lost_arbitration && r.error_passive && r.controller_problem);
  EXPECT_EQ(r.arbitration_bit, 12);
  EXPECT_EQ(r.text, "lost arbitration at bit 12; controller: error passive");
  EXPECT_TRUE(decodeBusError(makeRestartedFrame()).restarted);
  EXPECT_FALSE(decodeBusError(F(0x123, {})).valid);
}

TEST(Candump, FormatAndParse) {
  const CanFrame f = encodeCommand(1, {7, 500});
  EXPECT_EQ(formatCandumpLine(1700000000.123456, "can0", f), "(1700000000.123456) can0 201#07000000F4010000");
  double t = 0;
  std::string iface;
  CanFrame g;
  ASSERT_TRUE(parseCandumpLine("(1700000000.123456) can0 201#07000000F4010000\n", &t, &iface, &g));
  EXPECT_EQ(g, f);
  EXPECT_EQ(iface, "can0");
  EXPECT_NEAR(t, 1700000000.123456, 1e-6);
  ASSERT_TRUE(parseCandumpLine("(0000000001.000000) vcan_x 20000040#0000000000000000", &t, &iface, &g));
  EXPECT_TRUE(g.isError());
  EXPECT_FALSE(parseCandumpLine("(1.5) can0 123#00", &t, &iface, &g));
  EXPECT_FALSE(parseCandumpLine("(1700000000.000000) can0 800#00", &t, &iface, &g));                  // above 11 bits
  EXPECT_FALSE(parseCandumpLine("(1700000000.000000) can0 123#001", &t, &iface, &g));                 // odd digits
  EXPECT_FALSE(parseCandumpLine("(1700000000.000000) can0 123#000000000000000000", &t, &iface, &g));  // 9 bytes
}

}  // namespace
