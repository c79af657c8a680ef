#include <gtest/gtest.h>

#include "thorvald_twist_mux/twist_selector.h"

using thorvald_twist_mux::MuxConfig;
using thorvald_twist_mux::TwistSelector;
using thorvald_twist_mux::validateMuxConfig;

namespace {

// Inputs: teleop (prio 100, 0.5 s), nav (prio 10, 0.5 s), forever (prio 5, timeout 0), twin (prio 100, 0.5 s).
// Locks: safety (prio 255, no watchdog), joy_priority (prio 50, no watchdog), heartbeat (prio 20, watchdog 1 s).
MuxConfig exampleConfig() {
  MuxConfig c;
  c.inputs = {{"teleop", "teleop_joy/cmd_vel", 0.5, 100, false},
              {"nav", "nav_vel", 0.5, 10, false},
              {"forever", "slow", 0.0, 5, false},
              {"twin", "twin", 0.5, 100, false}};
  c.locks = {{"safety", "safety/lock", 0.0, 255, false},
             {"joy_priority", "teleop_joy/joy_priority", 0.0, 50, false},
             {"heartbeat", "heartbeat", 1.0, 20, false}};
  return c;
}

TwistSelector selectorWithHeartbeat(double now_s) {
  TwistSelector s(exampleConfig());
  s.acceptLock(2, false, now_s);  // keep the watchdog lock released
  return s;
}

}  // namespace

TEST(TwistSelector, NothingActiveBeforeAnyInput) {
  TwistSelector s = selectorWithHeartbeat(0.0);
  EXPECT_EQ(s.activeInput(0.0), TwistSelector::kNone);
  EXPECT_EQ(s.drivingInput(), TwistSelector::kNone);
  EXPECT_FALSE(s.takeDrivingLoss(0.0));
}

TEST(TwistSelector, HighestPriorityWins) {
  TwistSelector s = selectorWithHeartbeat(0.0);
  EXPECT_TRUE(s.acceptInput(1, 0.0));   // nav alone wins
  EXPECT_TRUE(s.acceptInput(0, 0.1));   // teleop outranks nav
  EXPECT_FALSE(s.acceptInput(1, 0.2));  // nav now outranked
  EXPECT_EQ(s.activeInput(0.2), 0);
}

TEST(TwistSelector, TieGoesToFirstListed) {
  TwistSelector s = selectorWithHeartbeat(0.0);
  EXPECT_TRUE(s.acceptInput(3, 0.0));  // twin alone
  EXPECT_TRUE(s.acceptInput(0, 0.1));  // teleop, same priority, listed first
  EXPECT_FALSE(s.acceptInput(3, 0.2));
}

TEST(TwistSelector, TimeoutIsStrict) {
  TwistSelector s = selectorWithHeartbeat(1.0);
  s.acceptInput(0, 1.0);
  EXPECT_FALSE(s.acceptInput(1, 1.5));  // age exactly 0.5 = timeout: still competing
  EXPECT_TRUE(s.acceptInput(1, 1.5001));
}

TEST(TwistSelector, ZeroTimeoutNeverExpires) {
  TwistSelector s = selectorWithHeartbeat(0.0);
  s.acceptInput(2, 0.0);
  EXPECT_FALSE(s.inputExpired(2, 1e6));
  s.acceptLock(2, false, 1e6);
  EXPECT_EQ(s.activeInput(1e6), 2);
}

TEST(TwistSelector, LockMasksStrictlyLowerPriority) {
  TwistSelector s = selectorWithHeartbeat(0.0);
  s.acceptLock(1, true, 0.0);           // joy_priority, 50
  EXPECT_FALSE(s.acceptInput(1, 0.1));  // nav (10) masked
  EXPECT_TRUE(s.acceptInput(0, 0.2));   // teleop (100) not masked
  s.acceptLock(0, true, 0.3);           // safety 255 masks everything
  EXPECT_FALSE(s.acceptInput(0, 0.31));
  EXPECT_EQ(s.activeInput(0.31), TwistSelector::kNone);
  s.acceptLock(0, false, 0.4);
  s.acceptLock(1, false, 0.4);
  EXPECT_FALSE(s.acceptInput(1, 0.6));  // teleop, last heard at 0.31 (masked but heard), still competing
  EXPECT_TRUE(s.acceptInput(1, 0.82));  // teleop timed out at 0.81
}

TEST(TwistSelector, LockOfEqualPriorityDoesNotMask) {
  MuxConfig c;
  c.inputs = {{"a", "a", 0.0, 50, false}};
  c.locks = {{"l", "l", 0.0, 50, false}};
  TwistSelector s(c);
  s.acceptLock(0, true, 0.0);
  EXPECT_TRUE(s.acceptInput(0, 0.0));
}

TEST(TwistSelector, WatchdogLockEngagedUntilHeardAndAfterSilence) {
  TwistSelector s(exampleConfig());
  EXPECT_TRUE(s.lockEngaged(2, 0.0));
  EXPECT_TRUE(s.lockByWatchdog(2, 0.0));
  EXPECT_FALSE(s.acceptInput(1, 0.0));  // nav (10) below heartbeat (20)
  s.acceptLock(2, false, 0.1);
  EXPECT_FALSE(s.lockEngaged(2, 1.1));  // age 1.0 = timeout
  EXPECT_TRUE(s.acceptInput(1, 1.1));
  EXPECT_TRUE(s.lockEngaged(2, 1.2));
  EXPECT_FALSE(s.acceptInput(1, 1.2));
  EXPECT_EQ(thorvald_twist_mux::engagedLockNames(s, 1.2), "heartbeat");
}

TEST(TwistSelector, DrivingLossOnTimeoutAndLockOnce) {
  TwistSelector s = selectorWithHeartbeat(0.0);
  ASSERT_TRUE(s.acceptInput(1, 0.0));
  EXPECT_FALSE(s.takeDrivingLoss(0.5));
  EXPECT_TRUE(s.takeDrivingLoss(0.51));
  EXPECT_FALSE(s.takeDrivingLoss(0.52));  // once
  ASSERT_TRUE(s.acceptInput(1, 0.6));
  s.acceptLock(0, true, 0.7);
  EXPECT_TRUE(s.takeDrivingLoss(0.7));
  EXPECT_FALSE(s.takeDrivingLoss(0.71));
}

TEST(TwistSelector, TakeoverIsNotALoss) {
  TwistSelector s = selectorWithHeartbeat(0.0);
  ASSERT_TRUE(s.acceptInput(1, 0.0));
  ASSERT_TRUE(s.acceptInput(0, 0.1));
  EXPECT_EQ(s.drivingInput(), 0);
  EXPECT_FALSE(s.takeDrivingLoss(0.55));  // nav expired, but teleop drives
  EXPECT_TRUE(s.takeDrivingLoss(0.61));   // teleop expired
}

TEST(MuxConfig, Validation) {
  MuxConfig c = exampleConfig();
  EXPECT_EQ(validateMuxConfig(c), "");
  MuxConfig neg = c;
  neg.inputs[1].timeout_s = -1.0;
  EXPECT_NE(validateMuxConfig(neg).find("topics[1] (nav): timeout is -1"), std::string::npos);
  MuxConfig dup = c;
  dup.locks[1].name = "safety";
  EXPECT_NE(validateMuxConfig(dup).find("locks[1] (safety): duplicate name"), std::string::npos);
  MuxConfig prio = c;
  prio.inputs[0].priority = 256;
  EXPECT_NE(validateMuxConfig(prio).find("priority is 256"), std::string::npos);
  MuxConfig empty;
  EXPECT_NE(validateMuxConfig(empty).find("no inputs"), std::string::npos);
  MuxConfig no_topic = c;
  no_topic.inputs[0].topic.clear();
  EXPECT_NE(validateMuxConfig(no_topic).find("topic is empty"), std::string::npos);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
