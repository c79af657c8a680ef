// The CiA 401 relay board: frame codec, the simulated board alone, and the host side against it on the virtual bus
// (fake clock: 2 ms simulator steps, 20 ms host cycles).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rig.h"
#include "thorvald_can_devices/canopen_protocol.h"
#include "thorvald_can_devices/cia401_protocol.h"
#include "thorvald_can_devices/io_board_sim.h"

using namespace thorvald_can_devices;

namespace {

TEST(Cia401Codec, OutputsFeedbackAndHeartbeatRoundTrip) {
  const CanFrame out = encodeIoOutputs(20, 0xA5);
  EXPECT_EQ(out.id, 0x214u);  // RPDO1 = 0x200 + node
  EXPECT_EQ(out.length, 1);
  EXPECT_EQ(out.data[0], 0xA5);
  EXPECT_EQ(*decodeIoOutputs(out), 0xA5);

  const CanFrame fb = encodeIoFeedback(20, {0x0F, 0x03});
  EXPECT_EQ(fb.id, 0x194u);  // TPDO1 = 0x180 + node
  EXPECT_EQ(toString(fb), "194#0F03");
  const auto decoded = decodeIoFeedback(fb);
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->inputs, 0x0F);
  EXPECT_EQ(decoded->outputs, 0x03);

  const CanFrame hb = encodeHeartbeat(20, kHeartbeatOperational);
  EXPECT_EQ(toString(hb), "714#05");
  EXPECT_EQ(*decodeHeartbeat(hb), kHeartbeatOperational);
  EXPECT_STREQ(nmtStateName(kHeartbeatPreOperational), "pre-operational");
}

TEST(Cia401Codec, RejectsMalformedFrames) {
  EXPECT_FALSE(decodeIoOutputs(makeFrame(0x214, {0x01, 0x00})));  // two bytes: not this board's mapping
  EXPECT_FALSE(decodeIoOutputs(makeFrame(0x214, {})));
  EXPECT_FALSE(decodeIoFeedback(makeFrame(0x194, {0x01})));
  EXPECT_FALSE(decodeHeartbeat(makeFrame(0x714, {0x33})));  // no such NMT state
  CanFrame remote = encodeIoOutputs(20, 1);
  remote.id |= kCanRtrFlag;
  EXPECT_FALSE(decodeIoOutputs(remote));
}

/// The simulated board alone on a bus, stepped by hand.
struct BoardBench {
  BoardBench() : name("iob" + std::to_string(::getpid())), board_bus(name), host(name), board(config()) {}
  static thorvald_base::IoConfig config() {
    thorvald_base::IoConfig c;
    c.name = "io0";
    c.id = 20;
    return c;
  }
  std::vector<CanFrame> step(double t) {
    CanFrame f;
    while (board_bus.receive(&f)) board.handle(f, board_bus, t);
    board.step(t, board_bus);
    std::vector<CanFrame> out;
    while (host.receive(&f)) out.push_back(f);
    return out;
  }
  std::string name;
  VirtualCanBus board_bus, host;
  IoBoardSim board;
};

TEST(IoBoardSim, BootsFollowsNmtAndEchoesOutputs) {
  BoardBench b;
  auto frames = b.step(0.0);
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(toString(frames[0]), "714#00");  // boot-up
  b.host.send(encodeIoOutputs(20, 0x01));    // pre-operational: PDOs are ignored
  b.step(0.01);
  EXPECT_EQ(b.board.outputs(), 0);
  b.host.send(encodeNmt(NmtCommand::kStart, 20));
  b.host.send(encodeIoOutputs(20, 0x05));
  frames = b.step(0.02);
  EXPECT_EQ(b.board.nmtState(), kHeartbeatOperational);
  EXPECT_EQ(b.board.outputs(), 0x05);
  bool echoed = false;
  for (const auto& f : frames) echoed = echoed || toString(f) == "194#0005";
  EXPECT_TRUE(echoed) << "the change is echoed at once";
  b.host.send(encodeNmt(NmtCommand::kStop, 0));  // all nodes
  b.step(0.03);
  EXPECT_EQ(b.board.outputs(), 0) << "a stopped board drops its relays";
}

TEST(IoBoardSim, OutputsDropWhenTheHostGoesQuiet) {
  BoardBench b;
  b.step(0.0);
  b.host.send(encodeNmt(NmtCommand::kStart, 20));
  b.host.send(encodeIoOutputs(20, 0x01));
  b.step(0.01);
  ASSERT_EQ(b.board.outputs(), 0x01);
  b.step(0.01 + cia401::kRpdoTimeoutS - 0.01);
  EXPECT_EQ(b.board.outputs(), 0x01);
  b.step(0.01 + cia401::kRpdoTimeoutS + 0.01);
  EXPECT_EQ(b.board.outputs(), 0) << "RPDO timeout: the outputs take their error value";
}

TEST(IoBoardSim, FaultsSilentAndStuck) {
  BoardBench b;
  EXPECT_FALSE(b.board.setFault("melted", true));
  b.step(0.0);
  b.host.send(encodeNmt(NmtCommand::kStart, 20));
  b.host.send(encodeIoOutputs(20, 0x01));
  b.step(0.01);
  ASSERT_TRUE(b.board.setFault("stuck", true));
  b.host.send(encodeIoOutputs(20, 0x00));
  b.step(0.02);
  EXPECT_EQ(b.board.outputs(), 0x01) << "a welded relay stays closed";
  ASSERT_TRUE(b.board.setFault("silent", true));
  EXPECT_TRUE(b.step(0.5).empty());
  EXPECT_EQ(b.board.outputs(), 0);
}

/// Index of board `name` in the rig's io boards.
thorvald_base::IoBoard& board(Rig& rig, const std::string& name) {
  for (auto& b : rig.io_boards) {
    if (b->name() == name) return *b;
  }
  throw std::runtime_error("no board " + name);
}

TEST(Cia401Board, StartsConfirmsAndSwitches) {
  Rig rig("robots/relay_boards.yaml");
  ASSERT_EQ(rig.io_boards.size(), 2u);
  EXPECT_TRUE(board(rig, "io0").status().state_unknown) << "nothing confirmed before the first echo";
  rig.run(0.3);
  auto s0 = board(rig, "io0").status();
  EXPECT_TRUE(s0.answering);
  EXPECT_FALSE(s0.state_unknown) << s0.why;
  EXPECT_EQ(s0.confirmed, 0x00);
  EXPECT_EQ(board(rig, "io1").status().confirmed, 0x02) << "rl1_init_state: output 1 closed at start";
  EXPECT_EQ(rig.sim.ioBoards()[1].outputs(), 0x02);

  rig.spied();
  board(rig, "io0").command(0, true);
  rig.run(0.04);
  EXPECT_EQ(rig.sim.ioBoards()[0].outputs(), 0x01);
  s0 = board(rig, "io0").status();
  EXPECT_EQ(s0.commanded, 0x01);
  EXPECT_EQ(s0.confirmed, 0x01);
  EXPECT_FALSE(s0.state_unknown);
  bool sent = false;
  for (const auto& f : rig.spied()) sent = sent || toString(f) == "214#01";
  EXPECT_TRUE(sent);
  board(rig, "io0").command(9, true);  // no such output: ignored
  EXPECT_EQ(board(rig, "io0").status().commanded, 0x01);
  rig.run(2.0);  // the host's refresh keeps the board's RPDO timeout from dropping the relay
  EXPECT_EQ(rig.sim.ioBoards()[0].outputs(), 0x01);
}

TEST(Cia401Board, SilentBoardPutsTheStateInDoubtUntilItEchoesAgain) {
  Rig rig("robots/relay_boards.yaml");
  rig.run(0.3);
  board(rig, "io0").command(0, true);
  rig.run(0.1);
  ASSERT_FALSE(board(rig, "io0").status().state_unknown);
  ASSERT_TRUE(rig.inject("io0", "silent", true));
  // Its last frame came at most one frame period (0.1 s) before: in doubt within 0.35 s + 0.1 s.
  rig.run(0.2);
  EXPECT_FALSE(board(rig, "io0").status().state_unknown) << "within the silence timeout (0.35 s)";
  rig.run(0.26);
  auto s = board(rig, "io0").status();
  EXPECT_TRUE(s.state_unknown);
  EXPECT_FALSE(s.answering);
  EXPECT_NE(s.why.find("silent"), std::string::npos) << s.why;
  EXPECT_FALSE(board(rig, "io1").status().state_unknown) << "the other board is not affected";
  // Powered again: boots, the host starts it (within 1 s) and sends the command; known once echoed.
  ASSERT_TRUE(rig.inject("io0", "silent", false));
  rig.run(1.5);
  s = board(rig, "io0").status();
  EXPECT_FALSE(s.state_unknown) << s.why;
  EXPECT_EQ(s.confirmed, 0x01);
}

TEST(Cia401Board, UnconfirmedCommandPutsTheStateInDoubt) {
  Rig rig("robots/relay_boards.yaml");
  rig.run(0.3);
  ASSERT_TRUE(rig.inject("io0", "stuck", true));
  board(rig, "io0").command(0, true);
  rig.run(0.2);
  EXPECT_FALSE(board(rig, "io0").status().state_unknown) << "within the confirm timeout (0.25 s)";
  rig.run(0.1);
  const auto s = board(rig, "io0").status();
  EXPECT_TRUE(s.state_unknown);
  EXPECT_TRUE(s.answering);
  EXPECT_NE(s.why.find("0x01 commanded, board echoes 0x00"), std::string::npos) << s.why;
}

TEST(Cia401Board, IdsAreOwnedAndBadNodesRefused) {
  Rig rig("robots/relay_boards.yaml");
  EXPECT_NE(rig.hw.canIdUser(0x214).find("io0"), std::string::npos);
  EXPECT_NE(rig.hw.canIdUser(0x195).find("io1"), std::string::npos);
  std::string why;
  thorvald_base::CanFrameData f;
  f.id = 0x214;
  f.length = 1;
  EXPECT_FALSE(rig.hw.sendRelayFrame(f, &why)) << "users cannot switch the relays through the CAN relay";
  auto config = rig.config;
  config.io[0].id = 0;
  CanBaseHardware hw(CanBaseOptions{0.0, "", 1000}, [] { return 0.0; });
  EXPECT_THROW(hw.initializeOnBus(config, std::make_unique<VirtualCanBus>(rig.bus_name + "x")),
               thorvald_base::ConfigError);
  config.io[0].id = 1;  // the drive controller's node: 0x181 is taken
  CanBaseHardware hw2(CanBaseOptions{0.0, "", 1000}, [] { return 0.0; });
  EXPECT_THROW(hw2.initializeOnBus(config, std::make_unique<VirtualCanBus>(rig.bus_name + "y")),
               thorvald_base::ConfigError);
}

}  // namespace
