// The rover's drive gate on the fusion's health (field_pose.h): it stops on localization_ok false with the fusion's
// reasons, stays stopped while the fusion is not ok, and resumes once it has been ok for the resume time.
#include <gtest/gtest.h>

#include "cotton_harvester_sim/field_pose.h"

namespace {

using cotton_harvester::sim::DriveGate;
using thorvald_navigation::FusionHealth;

FusionHealth ok() { return {}; }

FusionHealth notOk(const std::string& why) {
  FusionHealth h;
  h.level = FusionHealth::kError;
  h.localization_ok = false;
  h.reasons.push_back(why);
  return h;
}

TEST(DriveGate, DrivesWhileTheFusionIsOk) {
  DriveGate gate(0.5);
  for (double t = 0.0; t < 5.0; t += 0.02) EXPECT_FALSE(gate.update(ok(), t).has_value());
  EXPECT_FALSE(gate.stopped());
  EXPECT_EQ(gate.stops(), 0);
}

TEST(DriveGate, StopsOnNoFixSaysWhyAndResumesWhenOkAgain) {
  DriveGate gate(0.5);
  EXPECT_FALSE(gate.update(ok(), 0.0));
  const auto stop = gate.update(notOk("odom1 (odometry/gps): no message for 35.2 s"), 1.0);
  ASSERT_TRUE(stop.has_value());
  EXPECT_NE(stop->find("stopped: odom1 (odometry/gps): no message"), std::string::npos);
  EXPECT_TRUE(gate.stopped());
  EXPECT_NE(gate.reason().find("no message"), std::string::npos);
  // Still not ok: no new line, still stopped.
  EXPECT_FALSE(gate.update(notOk("odom1 (odometry/gps): no message for 36.0 s"), 2.0));
  EXPECT_TRUE(gate.stopped());
  // Ok again, but not yet for the resume time.
  EXPECT_FALSE(gate.update(ok(), 3.0));
  EXPECT_FALSE(gate.update(ok(), 3.4));
  EXPECT_TRUE(gate.stopped());
  const auto go = gate.update(ok(), 3.5);
  ASSERT_TRUE(go.has_value());
  EXPECT_NE(go->find("resumed"), std::string::npos);
  EXPECT_FALSE(gate.stopped());
  EXPECT_TRUE(gate.reason().empty());
  EXPECT_EQ(gate.stops(), 1);
  EXPECT_NEAR(gate.stoppedTotalS(), 2.5, 1e-9);
}

TEST(DriveGate, AFlickerOfOkDoesNotResume) {
  DriveGate gate(0.5);
  ASSERT_TRUE(gate.update(notOk("odom1 (odometry/gps): refused, pose: Mahalanobis 7.1 > 5"), 0.0));
  EXPECT_FALSE(gate.update(ok(), 0.1));
  EXPECT_FALSE(gate.update(notOk("imu0 (imu0/data): stale"), 0.3));  // not ok again: the ok time starts over
  EXPECT_FALSE(gate.update(ok(), 0.4));
  EXPECT_FALSE(gate.update(ok(), 0.8));
  EXPECT_TRUE(gate.stopped());
  EXPECT_EQ(gate.reason(), "imu0 (imu0/data): stale");  // ok now, waiting for the resume time
  EXPECT_TRUE(gate.update(ok(), 0.9));
  EXPECT_FALSE(gate.stopped());
  EXPECT_EQ(gate.stops(), 1);
}

TEST(DriveGate, StopsAgainAndCountsEachStop) {
  DriveGate gate(0.0);
  ASSERT_TRUE(gate.update(notOk("a"), 0.0));
  ASSERT_TRUE(gate.update(ok(), 1.0));
  ASSERT_TRUE(gate.update(notOk("b"), 2.0));
  EXPECT_EQ(gate.reason(), "b");
  ASSERT_TRUE(gate.update(ok(), 4.0));
  EXPECT_EQ(gate.stops(), 2);
  EXPECT_NEAR(gate.stoppedTotalS(), 3.0, 1e-9);
}

}  // namespace
