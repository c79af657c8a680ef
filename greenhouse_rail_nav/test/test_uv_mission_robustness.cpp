// The UV mission's returns and failures against the simulated greenhouse robot of simulated_greenhouse.h (no ROS):
// a return without floor, a pinned robot, per-set failures, silent range finders.
#include <gtest/gtest.h>

#include "simulated_greenhouse.h"

// Odometry runs 15 % ahead while reversing on 12 m rails: 0.5 m beyond the stored pose (0.8 m before the pipes,
// by odometry) the robot is still about 0.3 m on the rails and the return finds no floor. The robot reverses slowly
// until the floor is under the wheels, the set counts as treated with the reason in its report, and the mission goes on
// with the next set.
TEST(UvMissionRobustness, AReturnWithoutFloorIsRecoveredAndTheMissionGoesOn) {
  const std::vector<RailSetTruth> sets = {{0.0}, {1.6}};
  SimulatedGreenhouse world(sets, 13);
  world.odom_reverse_gain_on_rails = 1.15;
  grn::UvMissionParams p;
  grn::UvMission mission(world, p, targetsFor(sets, -1.2));
  EXPECT_EQ(mission.run(), "done");
  EXPECT_TRUE(mission.stopReason().empty()) << mission.stopReason();
  ASSERT_EQ(mission.reports().size(), 2u);
  for (const auto& r : mission.reports()) {
    EXPECT_TRUE(r.treated) << r.result;
    EXPECT_NE(r.result.find("no floor sensed at the stored pose"), std::string::npos) << r.result;
    EXPECT_NE(r.result.find("floor found after reversing"), std::string::npos) << r.result;
  }
  EXPECT_EQ(mission.done().size(), 2u);
  EXPECT_FALSE(world.wheel_past_edge);
  EXPECT_FALSE(world.lights_on_off_rails);
  EXPECT_LT(world.truePose().x, 0.0) << "the robot ends on the headland floor";
  if (HasFailure())
    for (const auto& l : world.lines) std::cout << l << "\n";
}

// Odometry 35 % ahead: the robot is still about 2 m on the rails when the recovery's limit is reached. Its state is
// not what the mission can handle: it stops there with the lights off and says why, and tries no other set.
TEST(UvMissionRobustness, StopsAndSaysWhyWhenTheFloorCannotBeFound) {
  const std::vector<RailSetTruth> sets = {{0.0}, {1.6}};
  SimulatedGreenhouse world(sets, 13);
  world.odom_reverse_gain_on_rails = 1.35;
  grn::UvMissionParams p;
  grn::UvMission mission(world, p, targetsFor(sets, -1.2));
  EXPECT_EQ(mission.run(), "aborted");
  EXPECT_NE(mission.stopReason().find("rail set 0"), std::string::npos) << mission.stopReason();
  EXPECT_NE(mission.stopReason().find("still on the rails after reversing"), std::string::npos) << mission.stopReason();
  ASSERT_EQ(mission.reports().size(), 1u);
  EXPECT_NE(mission.reports()[0].result.find("robot stopped"), std::string::npos) << mission.reports()[0].result;
  EXPECT_EQ(world.nav_goals, 1) << "no navigation towards the next set";
  EXPECT_FALSE(world.lights_on);
  EXPECT_EQ(world.lastLinearCommand(), 0.0);
  EXPECT_GT(world.truePose().x, 0.5) << "the robot is still on the rails";
  EXPECT_FALSE(world.wheel_past_edge);
  if (HasFailure())
    for (const auto& l : world.lines) std::cout << l << "\n";
}

// Backing off the rails the robot is pinned against something as its wheels reach the floor; its wheels turn on and
// odometry (heading off the robot's, turning only as the robot does) runs away from the stored pose, sideways or
// backwards. The return must stop with the reason, not drive on: each of the return's watches catches one case.
struct PinnedReturn {
  double odom_yaw_error_rad;
  double max_heading_error_rad;  ///< the heading watch's limit (3.14: effectively off)
  const char* expected_reason;
};

class UvMissionPinnedReturn : public ::testing::TestWithParam<PinnedReturn> {};

TEST_P(UvMissionPinnedReturn, ThePinnedRobotStopsWithTheReasonAndTheMissionGoesOn) {
  const PinnedReturn c = GetParam();
  const std::vector<RailSetTruth> sets = {{0.0}, {1.6}};
  SimulatedGreenhouse world(sets, 23);
  world.pinned_odom_yaw_error = c.odom_yaw_error_rad;
  grn::UvMissionParams p;
  p.rail_run.return_max_heading_error_rad = c.max_heading_error_rad;
  grn::UvMission mission(world, p, targetsFor(sets, -1.2));
  EXPECT_EQ(mission.run(), "done");
  ASSERT_EQ(mission.reports().size(), 2u);
  // The lamps lit the whole row: set 0 is treated, the failed return named in its report.
  EXPECT_TRUE(mission.reports()[0].treated) << mission.reports()[0].result;
  EXPECT_NE(mission.reports()[0].result.find(c.expected_reason), std::string::npos) << mission.reports()[0].result;
  EXPECT_TRUE(mission.reports()[1].treated) << mission.reports()[1].result;
  EXPECT_GT(world.pinned_driving_s, 0.0) << "the fault was never injected";
  // Driven no longer than the watch allows: the stall's 5 s, or the ~2.9 m odometry has left before it overruns, at the
  // return's slow 0.12 m/s.
  EXPECT_LT(world.pinned_driving_s, 30.0);
  EXPECT_FALSE(world.lights_on_off_rails);
  if (HasFailure())
    for (const auto& l : world.lines) std::cout << l << "\n";
}

INSTANTIATE_TEST_SUITE_P(
    Watches, UvMissionPinnedReturn,
    ::testing::Values(PinnedReturn{2.8, 0.5, "deg off the rails' line by odometry"},   // heading: at once
                      PinnedReturn{2.8, 3.14, "no progress towards the stored pose"},  // odometry goes away
                      PinnedReturn{1.4, 3.14, "without reaching the stored pose"}));   // odometry goes sideways

// A target pose with no rails in front of it: the search finds nothing, the set is reported with that reason, the
// robot stands on the floor, and the next sets are treated.
TEST(UvMissionRobustness, PerSetFailuresAreReportedAndTheMissionGoesOn) {
  const std::vector<RailSetTruth> sets = {{0.0}, {1.6}};
  SimulatedGreenhouse world(sets, 17);
  auto targets = targetsFor(sets, -1.2);
  grn::MissionTarget nowhere;
  nowhere.index = 7;
  nowhere.target_pose = thorvald_base::Pose2D(-1.2, -2.4, 0.0);  // no rails within the camera's reach
  targets.insert(targets.begin(), nowhere);
  grn::UvMissionParams p;
  p.max_align_attempts = 2;
  grn::UvMission mission(world, p, targets);
  EXPECT_EQ(mission.run(), "done");
  ASSERT_EQ(mission.reports().size(), 3u);
  EXPECT_EQ(mission.reports()[0].index, 7);
  EXPECT_FALSE(mission.reports()[0].treated);
  EXPECT_NE(mission.reports()[0].result.find("rails not found by the search"), std::string::npos)
      << mission.reports()[0].result;
  EXPECT_TRUE(mission.reports()[1].treated) << mission.reports()[1].result;
  EXPECT_TRUE(mission.reports()[2].treated) << mission.reports()[2].result;
  EXPECT_FALSE(world.wheel_past_edge);
  if (HasFailure())
    for (const auto& l : world.lines) std::cout << l << "\n";
}

// The range finders fall silent while the robot is on the rails: the treatment stops, and with no fresh reading
// nothing says where the robot stands, so the mission stops instead of driving on.
TEST(UvMissionRobustness, SilentRangeFindersOnTheRailsStopTheMission) {
  const std::vector<RailSetTruth> sets = {{0.0}, {1.6}};
  SimulatedGreenhouse world(sets, 19);
  world.nav_xy_error = world.nav_yaw_error = 0.0;
  world.silent_after_lights_s = 3.0;
  grn::UvMissionParams p;
  grn::UvMission mission(world, p, targetsFor(sets, -1.2));
  EXPECT_EQ(mission.run(), "aborted");
  ASSERT_EQ(mission.reports().size(), 1u);
  EXPECT_FALSE(mission.reports()[0].treated);
  EXPECT_NE(mission.stopReason().find("no fresh readings from the range finders"), std::string::npos)
      << mission.stopReason();
  EXPECT_FALSE(world.lights_on);
  EXPECT_EQ(world.lastLinearCommand(), 0.0);
  EXPECT_EQ(world.nav_goals, 1);
  EXPECT_TRUE(logSays(world, "mission stopped, not safe to go on"));
  if (HasFailure())
    for (const auto& l : world.lines) std::cout << l << "\n";
}

// A trolley parked 0.45 m behind the rear range finders at the target pose: each alignment's run-up reverse is held by
// it, and after zone/behind_wait the step ends where the robot stands; the alignment goes on from there and the
// mission ends, never held for good, the rear never nearer the trolley than it stood.
TEST(UvMissionRobustness, SomethingParkedBehindTheTargetPoseCutsTheAlignmentsReverseShort) {
  const std::vector<RailSetTruth> sets = {{0.0}, {1.6}};
  SimulatedGreenhouse world(sets, 3);
  world.obstacle_behind_x = -0.8 - 0.87 - 0.45;
  world.nav_xy_error = 0.06;
  grn::UvMissionParams p;
  ASSERT_DOUBLE_EQ(p.zone.behind_wait_s, 20.0);
  grn::UvMission mission(world, p, targetsFor(sets, -0.8));
  EXPECT_EQ(mission.run(), "done");
  ASSERT_TRUE(logSays(world, "align: reverse")) << "no alignment reversed: the case is not exercised";
  EXPECT_TRUE(logSays(world, "held 20 s for something behind"));
  EXPECT_TRUE(logSays(world, "' ends here"));
  EXPECT_GT(world.min_gap_behind, 0.3);
  ASSERT_EQ(mission.reports().size(), 2u);
  EXPECT_TRUE(mission.reports()[1].treated) << mission.reports()[1].result;
  if (HasFailure())
    for (const auto& l : world.lines) std::cout << l << "\n";
}
