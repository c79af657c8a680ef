#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "thorvald_navigation/goal_approach.h"

namespace tn = thorvald_navigation;

namespace {

// A 8 m x 5 m floor walled round with a pillar at (6.5, 1.0), a keep-out zone beyond y = 4.2 (the headland edge).
struct Floor {
  tn::Grid2D map{160, 100, 0.05, 0.0, 0.0, tn::kFree};
  tn::Grid2D keep_out{160, 100, 0.05, 0.0, 0.0, tn::kFree};
  Floor() {
    for (int x = 0; x < map.width; ++x) map.at(x, 0) = map.at(x, map.height - 1) = tn::kOccupied;
    for (int y = 0; y < map.height; ++y) map.at(0, y) = map.at(map.width - 1, y) = tn::kOccupied;
    for (int y = 0; y < map.height; ++y)
      for (int x = 0; x < map.width; ++x)
        if (map.centerOf(x, y).y() > 4.2) keep_out.at(x, y) = tn::kOccupied;
    for (int y = 18; y < 22; ++y)
      for (int x = 128; x < 132; ++x) map.at(x, y) = tn::kOccupied;
  }
};

const tn::Footprint kBox = tn::rectangleFootprint(-0.91, 0.23, -0.33, 0.33);

TEST(GoalApproach, RefusesGoalsOnTheKeepOutZoneWallsAndObstaclesWithTheReason) {
  const Floor f;
  tn::Costmap cm(f.map, f.keep_out, tn::CostmapParams{});
  const tn::Pose2D start{2.0, 2.0, 0.0};
  auto plan = [&](const tn::Pose2D& g) { return tn::planToGoal(cm, kBox, start, g, tn::PlannerParams{}, 0.3); };
  tn::GoalPlan r = plan({5.0, 4.1, tn::kPi / 2});  // its front over the edge
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.blocked_by_obstacle);
  EXPECT_NE(r.error.find("keep-out"), std::string::npos) << r.error;
  r = plan({6.8, 1.0, 0.0});  // over the pillar
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("wall"), std::string::npos) << r.error;
  cm.setObstacles({{5.0, 2.0}});
  r = plan({5.2, 2.0, 0.0});
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.blocked_by_obstacle) << r.error;
  r = plan({std::nan(""), 2.0, 0.0});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("finite"), std::string::npos);
}

// A differential robot's path ends with the final approach: straight along the goal's heading for its length, the
// plan's points inside that stretch dropped; over random goals on the floor.
TEST(GoalApproach, PathEndsWithTheFinalApproachAlongTheGoalsHeading) {
  const Floor f;
  const tn::Costmap cm(f.map, f.keep_out, tn::CostmapParams{});
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> x(1.5, 6.5), y(1.3, 3.0), yaw(-tn::kPi, tn::kPi);
  int checked = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const tn::Pose2D start{x(rng), y(rng), yaw(rng)}, goal{x(rng), y(rng), yaw(rng)};
    const tn::GoalPlan r = tn::planToGoal(cm, kBox, start, goal, tn::PlannerParams{}, 0.3);
    if (!r.ok) continue;  // a footprint near a wall at a random heading
    ++checked;
    ASSERT_GE(r.path.size(), 2u);
    const Eigen::Vector2d g(goal.x, goal.y), last = r.path.back(), pre = r.path.end()[-2];
    EXPECT_LT((last - g).norm(), 1e-9);
    if ((Eigen::Vector2d(start.x, start.y) - g).norm() < 0.4) continue;
    EXPECT_NEAR((g - pre).norm(), 0.3, 1e-9) << trial;
    EXPECT_NEAR(std::atan2(g.y() - pre.y(), g.x() - pre.x()), goal.yaw, 1e-6) << trial;
    // Omnidirectional (no approach): the plan as it is.
    const tn::GoalPlan omni = tn::planToGoal(cm, kBox, start, goal, tn::PlannerParams{}, 0.0);
    ASSERT_TRUE(omni.ok);
    EXPECT_LT((omni.path.back() - g).norm(), 1e-9);
  }
  EXPECT_GT(checked, 15);
  // No approach where it would put the footprint over the edge: the goal faces away from the edge, 0.5 m before it,
  // so the approach's start lies beyond.
  const tn::Pose2D near_edge{4.0, 3.9, -tn::kPi / 2};
  const auto path = tn::withFinalApproach(cm, kBox, {{2.0, 2.0}, {4.0, 3.9}}, near_edge, 0.5);
  EXPECT_EQ(path.size(), 2u);
}

// Settled past the goal, facing its way: the robot backs straight off to the approach's start, then drives it.
TEST(GoalApproach, ApproachAgainBacksOffStraightForADifferentialRobot) {
  const Floor f;
  const tn::Costmap cm(f.map, f.keep_out, tn::CostmapParams{});
  const tn::Pose2D goal{4.0, 2.0, 0.3};
  const tn::Pose2D settled{goal.x + 0.02, goal.y - 0.015, goal.yaw + 0.01};
  const tn::Approach a = tn::approachAgain(cm, kBox, settled, goal, 0.3, false);
  EXPECT_TRUE(a.reverse);
  EXPECT_TRUE(a.then_to_goal);
  EXPECT_NEAR(a.first_target.x, goal.x - 0.3 * std::cos(goal.yaw), 1e-9);
  EXPECT_NEAR(a.first_target.y, goal.y - 0.3 * std::sin(goal.yaw), 1e-9);
  EXPECT_NEAR(a.first_target.yaw, goal.yaw, 1e-12);
  const tn::Approach omni = tn::approachAgain(cm, kBox, settled, goal, 0.3, true);
  EXPECT_FALSE(omni.reverse);
  EXPECT_FALSE(omni.then_to_goal);
  EXPECT_NEAR(omni.first_target.x, goal.x, 1e-12);
}

TEST(GoalApproach, ArrivalJudgeCountsCorrectionsThenFails) {
  tn::ArrivalParams p;
  p.xy_tolerance_m = 0.01;
  p.yaw_tolerance_rad = 0.015;
  p.max_corrections = 2;
  ASSERT_EQ(p.validate(), "");
  tn::ArrivalJudge j(p);
  const tn::Pose2D goal{1.0, 2.0, 0.5};
  EXPECT_EQ(j.judge({1.006, 2.006, 0.51}, goal).verdict, tn::ArrivalVerdict::kReached);
  EXPECT_EQ(j.judge({1.009, 2.006, 0.51}, goal).verdict, tn::ArrivalVerdict::kApproachAgain);  // 1.08 cm
  EXPECT_EQ(j.judge({1.0, 2.0, 0.52}, goal).verdict, tn::ArrivalVerdict::kApproachAgain);      // 0.02 rad
  const tn::ArrivalJudgement last = j.judge({1.0, 2.03, 0.5}, goal);
  EXPECT_EQ(last.verdict, tn::ArrivalVerdict::kFailed);
  EXPECT_NEAR(last.xy_err_m, 0.03, 1e-9);
  EXPECT_NE(last.reason.find("2 corrections"), std::string::npos) << last.reason;
  j.reset();
  EXPECT_EQ(j.judge({1.0, 2.03, 0.5}, goal).verdict, tn::ArrivalVerdict::kApproachAgain);
  EXPECT_EQ(j.judge({std::nan(""), 2.0, 0.5}, goal).verdict, tn::ArrivalVerdict::kFailed);
  tn::ArrivalParams bad;
  bad.max_corrections = -1;
  EXPECT_NE(bad.validate(), "");
}

}  // namespace
