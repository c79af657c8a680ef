#include <gtest/gtest.h>

#include "thorvald_teleop/key_decoder.h"
#include "thorvald_teleop/keyboard_command.h"

using namespace thorvald_teleop;

TEST(KeyDecoder, ArrowsLettersAndSplitSequences) {
  KeyDecoder d;
  auto keys = d.feed("w\x1b[A\x1bOD");
  ASSERT_EQ(keys.size(), 3u);
  EXPECT_EQ(keys[0].character, 'w');
  EXPECT_EQ(keys[1].kind, KeyPress::Kind::kUp);
  EXPECT_EQ(keys[2].kind, KeyPress::Kind::kLeft);
  EXPECT_TRUE(d.feed("\x1b").empty());
  EXPECT_TRUE(d.feed("[").empty());
  keys = d.feed("C");
  ASSERT_EQ(keys.size(), 1u);
  EXPECT_EQ(keys[0].kind, KeyPress::Kind::kRight);
  keys = d.feed("\x1b[1;5Bx");  // ctrl-down: dropped, then x
  ASSERT_EQ(keys.size(), 1u);
  EXPECT_EQ(keys[0].character, 'x');
}

TEST(KeyboardCommand, MotionStepsStopAndTimeout) {
  KeyboardConfig c;
  c.linear_speed_max = 1.0;
  c.angular_speed_max = 2.0;
  c.gain = 0.5;
  c.key_timeout_s = 0.5;
  KeyboardCommand k(c);
  auto a = k.onKey({KeyPress::Kind::kUp, 0}, 0.0);
  ASSERT_TRUE(a.command);
  EXPECT_DOUBLE_EQ(a.command->linear_x, 0.5);
  a = k.onKey({KeyPress::Kind::kCharacter, 'a'}, 0.1);
  EXPECT_DOUBLE_EQ(a.command->linear_x, 0.0);
  EXPECT_DOUBLE_EQ(a.command->angular_z, 1.0);
  a = k.onKey({KeyPress::Kind::kCharacter, '+'}, 0.2);
  EXPECT_TRUE(a.gain_changed);
  EXPECT_NEAR(a.command->angular_z, 1.2, 1e-12);
  a = k.onKey({KeyPress::Kind::kCharacter, 'e'}, 0.3);
  EXPECT_NEAR(a.command->linear_y, -0.6, 1e-12);
  EXPECT_FALSE(k.onTimer(0.8).command);
  a = k.onTimer(0.81);
  ASSERT_TRUE(a.command);
  EXPECT_TRUE(a.command->isZero());
  EXPECT_FALSE(k.onTimer(0.9).command);
  k.onKey({KeyPress::Kind::kCharacter, 's'}, 1.0);
  a = k.onKey({KeyPress::Kind::kCharacter, ' '}, 1.1);
  EXPECT_TRUE(a.command->isZero());
  a = k.onKey({KeyPress::Kind::kCharacter, 0x03}, 1.2);
  EXPECT_TRUE(a.quit);
  EXPECT_TRUE(a.command->isZero());
}

TEST(KeyboardCommand, GainClampsAndHelpListsKeys) {
  KeyboardConfig c;
  KeyboardCommand k(c);
  for (int i = 0; i < 20; ++i) k.onKey({KeyPress::Kind::kCharacter, '-'}, 0.0);
  EXPECT_NEAR(k.gain(), c.gain_min, 1e-12);
  const std::string help = keyboardHelp(c, k.gain());
  for (const char* needle : {"w / Up", "space", "Ctrl-C", "crab left", "0.10 m/s"}) {
    EXPECT_NE(help.find(needle), std::string::npos) << needle;
  }
  c.gain = 5.0;
  EXPECT_FALSE(validateKeyboardConfig(c).empty());
}
