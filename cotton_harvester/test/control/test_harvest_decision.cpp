#include <gtest/gtest.h>

#include "cotton_harvester/control/harvest_decision.h"

using namespace cotton_harvester::control;

namespace {
const DecisionParams kParams;  // y, z tolerance 3 cm, reach 37 cm
const Point3 kEffector{0.0, 0.0, 0.8};
}  // namespace

TEST(HarvestDecision, BollAheadMovesForwardByTheDifference) {
  const HarvestDecision d = decide(Point3{0.1, 0.25, 0.9}, kEffector, kParams);
  EXPECT_EQ(d.action, HarvestAction::kForward);
  EXPECT_DOUBLE_EQ(d.rover_move_m, 0.25);
}

TEST(HarvestDecision, BollBehindMovesBackward) {
  const HarvestDecision d = decide(Point3{0.1, -0.1, 0.9}, kEffector, kParams);
  EXPECT_EQ(d.action, HarvestAction::kBackward);
  EXPECT_DOUBLE_EQ(d.rover_move_m, -0.1);
  DecisionParams flipped = kParams;
  flipped.y_forward_sign = -1.0;  // camera y grows backwards on this mounting
  EXPECT_DOUBLE_EQ(decide(Point3{0.1, -0.1, 0.9}, kEffector, flipped).rover_move_m, 0.1);
}

TEST(HarvestDecision, AlignedAndDeeperEffectorMovesTheArmUp) {
  // Zm (0.8) > Zb (0.6): the end effector is below the boll.
  const HarvestDecision d = decide(Point3{0.1, 0.02, 0.6}, kEffector, kParams);
  EXPECT_EQ(d.action, HarvestAction::kArmUp);
  EXPECT_DOUBLE_EQ(d.arm_depth_m, 0.6);
}

TEST(HarvestDecision, AlignedAndHigherEffectorMovesTheArmDown) {
  const HarvestDecision d = decide(Point3{0.1, -0.02, 0.95}, kEffector, kParams);
  EXPECT_EQ(d.action, HarvestAction::kArmDown);
  EXPECT_DOUBLE_EQ(d.arm_depth_m, 0.95);
}

TEST(HarvestDecision, AlignedWithinReachPicks) {
  const HarvestDecision d = decide(Point3{0.2, 0.01, 0.82}, kEffector, kParams);
  EXPECT_EQ(d.action, HarvestAction::kPick);
  EXPECT_DOUBLE_EQ(d.pick_offset_m, 0.2);
  EXPECT_EQ(decide(Point3{-0.36, 0.0, 0.8}, kEffector, kParams).action, HarvestAction::kPick);
}

TEST(HarvestDecision, AlignedOutOfReachIsReported) {
  EXPECT_EQ(decide(Point3{0.38, 0.0, 0.8}, kEffector, kParams).action, HarvestAction::kOutOfReach);
}

TEST(HarvestDecision, TolerancesDefineEqual) {
  // Just inside the Y tolerance: treated as aligned.
  EXPECT_EQ(decide(Point3{0.0, 0.029, 0.8}, kEffector, kParams).action, HarvestAction::kPick);
  EXPECT_EQ(decide(Point3{0.0, 0.031, 0.8}, kEffector, kParams).action, HarvestAction::kForward);
  EXPECT_EQ(decide(Point3{0.0, 0.0, 0.829}, kEffector, kParams).action, HarvestAction::kPick);
  EXPECT_EQ(decide(Point3{0.0, 0.0, 0.831}, kEffector, kParams).action, HarvestAction::kArmDown);
  DecisionParams loose = kParams;
  loose.y_tolerance_m = 0.05;
  EXPECT_EQ(decide(Point3{0.0, 0.04, 0.8}, kEffector, loose).action, HarvestAction::kPick);
}

TEST(HarvestDecision, ParamsCheck) {
  DecisionParams params;
  EXPECT_EQ(params.check(), "");
  params.y_forward_sign = 0.5;
  EXPECT_NE(params.check().find("y_forward_sign"), std::string::npos);
  params = DecisionParams();
  params.pick_reach_m = 0.0;
  EXPECT_NE(params.check().find("pick_reach_m"), std::string::npos);
  EXPECT_STREQ(toString(HarvestAction::kArmUp), "arm_up");
}
