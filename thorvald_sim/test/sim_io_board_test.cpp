// The simulated relay board: switches at once, confirmed after the echo delay; silent -> state unknown after the
// silence timeout, relays off; stuck -> a new command is contradicted by the echo and the state becomes unknown.
#include <gtest/gtest.h>

#include <vector>

#include "thorvald_sim/sim_io_board.h"

namespace thorvald_sim {
namespace {

thorvald_base::IoConfig io0() {
  thorvald_base::IoConfig c;
  c.name = "io0";
  c.id = 20;
  return c;
}

// Runs base_driver's 50 Hz cycle from `from_s` to `to_s`; returns the first time the state was known (or -1).
double run(SimIoBoard& board, double from_s, double to_s) {
  double known = -1.0;
  for (double t = from_s; t <= to_s + 1e-9; t += 0.02) {
    board.update(t);
    if (known < 0.0 && !board.status().state_unknown) known = t;
  }
  return known;
}

TEST(SimIoBoard, SwitchesAtOnceAndConfirmsAfterTheEchoDelay) {
  SimIoBoardSettings s;
  s.echo_delay_s = 0.04;
  SimIoBoard board(io0(), s);
  std::vector<uint8_t> truth;
  board.on_outputs = [&truth](uint8_t v) { truth.push_back(v); };
  EXPECT_TRUE(board.status().state_unknown);
  EXPECT_NEAR(run(board, 0.0, 0.2), 0.04, 0.021);  // first echo of the initial outputs
  ASSERT_EQ(truth.size(), 1u);
  EXPECT_EQ(truth[0], 0);

  board.command(0, true);
  EXPECT_EQ(board.outputs(), 0x01);  // the relay switched with the command
  ASSERT_EQ(truth.size(), 2u);
  EXPECT_EQ(truth[1], 0x01);
  board.update(0.22);  // the echo of the old state keeps the last verdict within the confirm timeout
  EXPECT_FALSE(board.status().state_unknown);
  EXPECT_EQ(board.status().confirmed, 0x00);
  board.update(0.24);
  EXPECT_EQ(board.status().confirmed, 0x01);
  EXPECT_EQ(board.status().commanded, 0x01);
  EXPECT_TRUE(board.status().answering);
  board.command(9, true);  // out of range: ignored
  EXPECT_EQ(board.status().commanded, 0x01);
}

TEST(SimIoBoard, InitialStateFromTheRobotFile) {
  auto c = io0();
  c.rl1_init_state = 1;
  SimIoBoard board(c, {});
  board.update(0.0);
  EXPECT_EQ(board.outputs(), 0x02);
  run(board, 0.02, 0.1);
  EXPECT_FALSE(board.status().state_unknown);
  EXPECT_EQ(board.status().confirmed, 0x02);
}

TEST(SimIoBoard, SilentBoardPutsTheStateInDoubtAndDropsItsRelays) {
  SimIoBoardSettings s;
  s.silent_after_s = 1.0;
  SimIoBoard board(io0(), s);
  uint8_t truth = 0xFF;
  board.on_outputs = [&truth](uint8_t v) { truth = v; };
  board.update(0.0);
  board.command(0, true);
  run(board, 0.02, 0.98);
  EXPECT_FALSE(board.status().state_unknown);
  EXPECT_EQ(truth, 0x01);
  board.update(1.0);
  EXPECT_TRUE(board.silent());
  EXPECT_EQ(truth, 0x00);  // unpowered
  // Last echo at most one echo period before; unknown once the silence timeout (0.35 s) has passed since.
  double unknown_at = -1.0;
  for (double t = 1.02; t < 2.0 && unknown_at < 0.0; t += 0.02) {
    board.update(t);
    if (board.status().state_unknown) unknown_at = t;
  }
  ASSERT_GT(unknown_at, 0.0);
  EXPECT_LE(unknown_at, 1.0 + 0.35 + 0.02 + 1e-6);
  const auto st = board.status();
  EXPECT_FALSE(st.answering);
  EXPECT_NE(st.why.find("board silent for"), std::string::npos) << st.why;
  board.command(0, false);  // a silent board hears nothing: still unknown
  run(board, 2.0, 3.0);
  EXPECT_TRUE(board.status().state_unknown);
}

TEST(SimIoBoard, StuckRelayIsContradictedByTheEcho) {
  SimIoBoardSettings s;
  s.stuck_after_s = 0.5;
  SimIoBoard board(io0(), s);
  board.update(0.0);
  board.command(0, true);
  run(board, 0.02, 0.6);
  ASSERT_TRUE(board.stuck());
  EXPECT_FALSE(board.status().state_unknown);
  board.command(0, false);  // welded: the lamps stay on
  EXPECT_EQ(board.outputs(), 0x01);
  run(board, 0.62, 0.84);  // within the confirm timeout (0.25 s): the last verdict
  EXPECT_FALSE(board.status().state_unknown);
  run(board, 0.88, 1.2);
  const auto st = board.status();
  EXPECT_TRUE(st.state_unknown);
  EXPECT_TRUE(st.answering);
  EXPECT_EQ(st.why, "outputs 0x00 commanded, board echoes 0x01");
}

}  // namespace
}  // namespace thorvald_sim
