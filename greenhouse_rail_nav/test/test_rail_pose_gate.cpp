#include <gtest/gtest.h>

#include "greenhouse_rail_nav/rail_pose_gate.h"

using namespace greenhouse_rail_nav;
using Verdict = RailPoseGate::Verdict;

TEST(RailPoseGate, AcceptsConsistentEstimates) {
  RailPoseGate gate{RailPoseGateParams()};
  EXPECT_EQ(gate.update(thorvald_base::Pose2D(-0.8, 0.0, 0.0), 0.0), Verdict::kAccepted);
  EXPECT_EQ(gate.update(thorvald_base::Pose2D(-0.75, 0.02, 0.01), 0.1), Verdict::kAccepted);
  EXPECT_NEAR(gate.accepted()->x, -0.75, 1e-12);
}

TEST(RailPoseGate, HoldsBackAJumpUntilItRepeats) {
  RailPoseGateParams params;
  params.frames_to_accept_jump = 3;
  RailPoseGate gate(params);
  gate.update(thorvald_base::Pose2D(-0.8, 0.0, 0.0), 0.0);
  EXPECT_EQ(gate.update(thorvald_base::Pose2D(-0.8, 0.3, 0.0), 0.1), Verdict::kHeldBack);
  EXPECT_EQ(gate.update(thorvald_base::Pose2D(-0.8, 0.31, 0.0), 0.2), Verdict::kHeldBack);
  EXPECT_EQ(gate.heldBack(), 2);
  EXPECT_NEAR(gate.accepted()->y, 0.0, 1e-12);
  EXPECT_EQ(gate.update(thorvald_base::Pose2D(-0.8, 0.3, 0.01), 0.3), Verdict::kAcceptedJump);
  EXPECT_NEAR(gate.accepted()->y, 0.3, 1e-12);
  EXPECT_EQ(gate.update(thorvald_base::Pose2D(-0.8, 0.3, 0.0), 0.4), Verdict::kAccepted);
}

TEST(RailPoseGate, ScatteredOutliersNeverGetThrough) {
  RailPoseGate gate{RailPoseGateParams()};
  gate.update(thorvald_base::Pose2D(-0.8, 0.0, 0.0), 0.0);
  // Outliers that disagree with each other as well: each restarts the count.
  const double ys[] = {0.4, -0.4, 0.4, -0.4, 0.4, -0.4};
  double t = 0.1;
  for (const double y : ys) {
    EXPECT_EQ(gate.update(thorvald_base::Pose2D(-0.8, y, 0.0), t), Verdict::kHeldBack);
    t += 0.1;
  }
  EXPECT_EQ(gate.update(thorvald_base::Pose2D(-0.8, 0.01, 0.0), t), Verdict::kAccepted);
}

TEST(RailPoseGate, YawJumpIsInconsistentAndStaleHistoryIsForgotten) {
  RailPoseGate gate{RailPoseGateParams()};
  gate.update(thorvald_base::Pose2D(-0.8, 0.0, 0.0), 0.0);
  EXPECT_EQ(gate.update(thorvald_base::Pose2D(-0.8, 0.0, 0.2), 0.1), Verdict::kHeldBack);
  // Nothing accepted for longer than reset_after_s: the next estimate is taken as it comes.
  EXPECT_EQ(gate.update(thorvald_base::Pose2D(-0.8, 0.0, 0.4), 5.0), Verdict::kAccepted);
  gate.reset();
  EXPECT_FALSE(gate.accepted().has_value());
}

TEST(RailPoseGate, Validation) {
  RailPoseGateParams p;
  EXPECT_EQ(p.validate(), "");
  p.frames_to_accept_jump = 0;
  EXPECT_NE(p.validate().find("frames_to_accept_jump"), std::string::npos);
}
