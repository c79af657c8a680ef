#include <limits>

#include <gtest/gtest.h>

#include "thorvald_navigation/localization_gate.h"

namespace tn = thorvald_navigation;
using tn::GateAction;
using tn::LocalizerState;

namespace {

tn::LocalizationGateParams params() {
  tn::LocalizationGateParams p;
  p.lost_wait_s = 10.0;
  p.uncertain_wait_s = 4.0;
  return p;
}

TEST(LocalizationGate, ParsesTheLocalizersStatusTexts) {
  LocalizerState s = LocalizerState::kUnknown;
  EXPECT_TRUE(tn::parseLocalizerState("localized", &s));
  EXPECT_EQ(s, LocalizerState::kLocalized);
  EXPECT_TRUE(tn::parseLocalizerState("uncertain", &s));
  EXPECT_EQ(s, LocalizerState::kUncertain);
  EXPECT_TRUE(tn::parseLocalizerState("lost", &s));
  EXPECT_EQ(s, LocalizerState::kLost);
  EXPECT_TRUE(tn::parseLocalizerState("no pose", &s));
  EXPECT_EQ(s, LocalizerState::kNoPose);
  for (const char* bad : {"", "Lost", "localised", "lost ", "ok"}) {
    EXPECT_FALSE(tn::parseLocalizerState(bad, &s)) << bad;
    EXPECT_EQ(s, LocalizerState::kNoPose) << "untouched by '" << bad << "'";
  }
}

TEST(LocalizationGate, WithoutAnyStatusItAlwaysDrives) {  // amcl publishes no status
  const tn::LocalizationGate gate(params());
  EXPECT_EQ(gate.whileDriving(1000.0, 0.0).action, GateAction::kDrive);
  EXPECT_EQ(gate.atGoal(1000.0, 0.0, 999.0).action, GateAction::kDrive);
}

TEST(LocalizationGate, LostHoldsThenAbortsWithTheReason) {
  tn::LocalizationGate gate(params());
  gate.setStatus(LocalizerState::kLocalized, 0.0);
  EXPECT_EQ(gate.whileDriving(5.0, 1.0).action, GateAction::kDrive);
  gate.setStatus(LocalizerState::kLost, 20.0);
  const tn::GateVerdict hold = gate.whileDriving(25.0, 1.0);
  EXPECT_EQ(hold.action, GateAction::kHold);
  EXPECT_NE(hold.reason.find("lost"), std::string::npos) << hold.reason;
  EXPECT_EQ(gate.whileDriving(29.9, 1.0).action, GateAction::kHold);
  const tn::GateVerdict give_up = gate.whileDriving(30.1, 1.0);
  EXPECT_EQ(give_up.action, GateAction::kAbort);
  EXPECT_NE(give_up.reason.find("lost for 10.1 s"), std::string::npos) << give_up.reason;
  // Lost at the goal as well as on the way.
  EXPECT_EQ(gate.atGoal(25.0, 1.0, 24.0).action, GateAction::kHold);
  EXPECT_EQ(gate.atGoal(31.0, 1.0, 24.0).action, GateAction::kAbort);
  // Relocalised: drives again.
  gate.setStatus(LocalizerState::kUncertain, 29.0);
  EXPECT_EQ(gate.whileDriving(31.0, 1.0).action, GateAction::kDrive);
}

TEST(LocalizationGate, WaitingCountsFromTheGoalsStartWhenLostBeforeIt) {
  tn::LocalizationGate gate(params());
  gate.setStatus(LocalizerState::kNoPose, 0.0);
  EXPECT_EQ(gate.whileDriving(105.0, 100.0).action, GateAction::kHold);
  EXPECT_EQ(gate.whileDriving(111.0, 100.0).action, GateAction::kAbort);
  // Repeating the same status does not restart the clock.
  gate.setStatus(LocalizerState::kNoPose, 50.0);
  EXPECT_EQ(gate.whileDriving(11.0, 0.0).action, GateAction::kAbort);
}

TEST(LocalizationGate, UncertainDrivesButTheGoalWaitsForACertainPose) {
  tn::LocalizationGate gate(params());
  gate.setStatus(LocalizerState::kUncertain, 0.0);
  EXPECT_EQ(gate.whileDriving(100.0, 0.0).action, GateAction::kDrive);
  // Arrived at 100 s: uncertain for 50 s already, but the wait counts from the arrival.
  EXPECT_EQ(gate.atGoal(101.0, 0.0, 100.0).action, GateAction::kHold);
  const tn::GateVerdict v = gate.atGoal(104.5, 0.0, 100.0);
  EXPECT_EQ(v.action, GateAction::kAbort);
  EXPECT_NE(v.reason.find("uncertain"), std::string::npos) << v.reason;
  gate.setStatus(LocalizerState::kLocalized, 102.0);
  EXPECT_EQ(gate.atGoal(104.5, 0.0, 100.0).action, GateAction::kDrive);
}

TEST(LocalizationGate, ParametersAreChecked) {
  tn::LocalizationGateParams p;
  EXPECT_EQ(p.validate(), "");
  p.lost_wait_s = 0.0;
  EXPECT_NE(p.validate(), "");
  p.lost_wait_s = 5.0;
  p.uncertain_wait_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(p.validate(), "");
}

}  // namespace
