#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "thorvald_navigation/goal_approach.h"

namespace tn = thorvald_navigation;

namespace {

// A 8 m x 5 m floor walled round with a pillar at (6.5, 1.0), a keep-out zone beyond y = 4.2 (the headland edge).
struct Floor {
  thorvald_map::OccupancyGrid map{160, 100, 0.05, 0.0, 0.0, thorvald_map::kFree};
  thorvald_map::OccupancyGrid keep_out{160, 100, 0.05, 0.0, 0.0, thorvald_map::kFree};
  Floor() {
    for (int x = 0; x < map.width; ++x) map.at(x, 0) = map.at(x, map.height - 1) = thorvald_map::kOccupied;
    for (int y = 0; y < map.height; ++y) map.at(0, y) = map.at(map.width - 1, y) = thorvald_map::kOccupied;
    for (int y = 0; y < map.height; ++y)
      for (int x = 0; x < map.width; ++x)
        if (map.cellCentre(x, y).y() > 4.2) keep_out.at(x, y) = thorvald_map::kOccupied;
    for (int y = 18; y < 22; ++y)
      for (int x = 128; x < 132; ++x) map.at(x, y) = thorvald_map::kOccupied;
  }
};

const tn::Footprint kBox = tn::rectangleFootprint(-0.91, 0.23, -0.33, 0.33);

TEST(GoalApproach, RefusesGoalsOnTheKeepOutZoneWallsAndObstaclesWithTheReason) {
  const Floor f;
  tn::Costmap cm(f.map, f.keep_out, tn::CostmapParams{});
  const thorvald_base::Pose2D start{2.0, 2.0, 0.0};
  auto plan = [&](const thorvald_base::Pose2D& g) {
    return tn::planToGoal(cm, kBox, start, g, tn::PlannerParams{}, 0.3);
  };
  tn::GoalPlan r = plan({5.0, 4.1, thorvald_base::kPi / 2});  // its front over the edge
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
  std::uniform_real_distribution<double> x(1.5, 6.5), y(1.3, 3.0), yaw(-thorvald_base::kPi, thorvald_base::kPi);
  int checked = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const thorvald_base::Pose2D start{x(rng), y(rng), yaw(rng)}, goal{x(rng), y(rng), yaw(rng)};
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
  const thorvald_base::Pose2D near_edge{4.0, 3.9, -thorvald_base::kPi / 2};
  const auto path = tn::withFinalApproach(cm, kBox, {{2.0, 2.0}, {4.0, 3.9}}, near_edge, 0.5);
  EXPECT_EQ(path.size(), 2u);
}

// Settled past the goal, facing its way: the robot backs straight off to the approach's start, then drives it.
TEST(GoalApproach, ApproachAgainBacksOffStraightForADifferentialRobot) {
  const Floor f;
  const tn::Costmap cm(f.map, f.keep_out, tn::CostmapParams{});
  const thorvald_base::Pose2D goal{4.0, 2.0, 0.3};
  const thorvald_base::Pose2D settled{goal.x + 0.02, goal.y - 0.015, goal.yaw + 0.01};
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
  const thorvald_base::Pose2D goal{1.0, 2.0, 0.5};
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

namespace {

// The greenhouse robot's frame: 1.05 m long behind and in front of its front axle (base_link), 0.92 m wide.
const tn::Footprint kFrame = tn::rectangleFootprint(-0.85, 0.2, -0.46, 0.46);

// An 8 m x 5 m floor, walled round, plus walls along y = from_y..to_y (rows) between x = 0.5 and 7.5 if asked.
tn::Costmap walledFloor(double corridor_low = -1.0, double corridor_high = -1.0) {
  thorvald_map::OccupancyGrid map{160, 100, 0.05, 0.0, 0.0, thorvald_map::kFree};
  for (int x = 0; x < map.width; ++x) map.at(x, 0) = map.at(x, map.height - 1) = thorvald_map::kOccupied;
  for (int y = 0; y < map.height; ++y) map.at(0, y) = map.at(map.width - 1, y) = thorvald_map::kOccupied;
  for (double wy : {corridor_low, corridor_high}) {
    if (wy < 0.0) continue;
    for (int x = 10; x < 150; ++x) map.at(x, static_cast<int>(wy / 0.05)) = thorvald_map::kOccupied;
  }
  return tn::Costmap(map, thorvald_map::OccupancyGrid{}, tn::CostmapParams{});
}

}  // namespace

// Beside a wall 0.8 m from its front axle, the robot must not turn its rear (0.97 m round) towards the wall: it backs
// along the path instead (a quarter turn away from the wall), then turns to the goal's heading at the final approach's
// start and drives that stretch forward.
TEST(GoalApproach, BesideAWallADifferentialRobotBacksAlongThePathRatherThanTurnItsRearIntoTheWall) {
  const tn::Costmap cm = walledFloor();
  const thorvald_base::Pose2D start{3.0, 4.15, 0.0}, goal{3.0, 2.55, 0.0};  // the wall's cells begin at y = 4.95
  const tn::GoalPlan plan = tn::planToGoal(cm, kFrame, start, goal, tn::PlannerParams{}, 0.3);
  ASSERT_TRUE(plan.ok) << plan.error;
  const tn::PathDirection d = tn::choosePathDirection(cm, kFrame, start, plan.path, goal, false);
  ASSERT_TRUE(d.ok) << d.error;
  EXPECT_TRUE(d.approach.reverse);
  EXPECT_TRUE(d.approach.then_to_goal);
  EXPECT_NEAR(d.approach.first_target.x, 2.7, 1e-6);
  EXPECT_NEAR(d.approach.first_target.y, 2.55, 1e-6);
  EXPECT_DOUBLE_EQ(d.approach.first_target.yaw, goal.yaw);
  // The forward way's first turn is the one that meets the wall.
  EXPECT_TRUE(tn::turnTouches(cm, kFrame, {3.0, 4.15}, 0.0, -thorvald_base::kPi / 2, tn::Blocker::kWall));
  EXPECT_FALSE(tn::turnTouches(cm, kFrame, {3.0, 4.15}, 0.0, thorvald_base::kPi / 2, tn::Blocker::kWall));
  // Omnidirectional robots are not checked here.
  const tn::PathDirection omni = tn::choosePathDirection(cm, kFrame, start, plan.path, goal, true);
  EXPECT_TRUE(omni.ok);
  EXPECT_FALSE(omni.approach.reverse);
}

// In the open, every path is driven forward, whole, over random starts and goals.
TEST(GoalApproach, InTheOpenPathsAreDrivenForward) {
  const tn::Costmap cm = walledFloor();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(2.0, 6.0), y(1.8, 3.2), yaw(-thorvald_base::kPi, thorvald_base::kPi);
  int checked = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const thorvald_base::Pose2D start{x(rng), y(rng), yaw(rng)}, goal{x(rng), y(rng), yaw(rng)};
    const tn::GoalPlan plan = tn::planToGoal(cm, kFrame, start, goal, tn::PlannerParams{}, 0.3);
    if (!plan.ok) continue;
    const tn::PathDirection d = tn::choosePathDirection(cm, kFrame, start, plan.path, goal, false);
    EXPECT_TRUE(d.ok) << d.error;
    EXPECT_FALSE(d.approach.reverse) << "trial " << trial;
    EXPECT_EQ(d.approach.first_leg.size(), plan.path.size());
    ++checked;
  }
  EXPECT_GE(checked, 10);
}

// A corridor 1.6 m wide: the final quarter turn sweeps a wall whichever way the robot drives: refused, naming it.
TEST(GoalApproach, ATurnNoDirectionClearsIsRefusedWithTheReason) {
  const tn::Costmap cm = walledFloor(2.0, 3.6);
  const thorvald_base::Pose2D start{2.0, 2.8, 0.0}, goal{5.0, 2.8, thorvald_base::kPi / 2};
  const tn::PathDirection d = tn::choosePathDirection(cm, kFrame, start, {{2.0, 2.8}, {5.0, 2.8}}, goal, false);
  EXPECT_FALSE(d.ok);
  EXPECT_NE(d.error.find("final turn"), std::string::npos) << d.error;
  EXPECT_NE(d.error.find("wall"), std::string::npos) << d.error;
}

// Standing with its frame on a wall's cells (a wall along y = 2.0 to 2.05, the frame down to y = 1.99), the cells it
// stands on are not held against its motions, but a turn that sweeps the frame further into the wall is: the quarter
// turn forward would swing the rear through it, so the robot backs away first (it used to turn into the wall).
TEST(GoalApproach, StandingOnAWallATurnFurtherIntoItIsRefused) {
  const tn::Costmap cm = walledFloor(2.0);
  const thorvald_base::Pose2D squeezed{3.0, 2.45, 0.0};
  const std::vector<Eigen::Vector2d> path{{3.0, 2.45}, {3.0, 3.8}, {5.0, 3.8}};
  ASSERT_TRUE(cm.footprintTouches(squeezed, kFrame, tn::Blocker::kWall));
  EXPECT_TRUE(tn::turnTouches(cm, kFrame, {3.0, 2.45}, 0.0, thorvald_base::kPi / 2, tn::Blocker::kWall));
  const std::vector<int> standing = cm.footprintCells(squeezed, kFrame, tn::Blocker::kWall);
  EXPECT_GE(standing.size(), 15u);  // the 1.05 m frame on 5 cm cells
  EXPECT_TRUE(
      tn::turnTouches(cm, kFrame, {3.0, 2.45}, 0.0, thorvald_base::kPi / 2, tn::Blocker::kWall, 0.05, &standing));
  EXPECT_FALSE(
      tn::turnTouches(cm, kFrame, {3.0, 2.45}, 0.0, -thorvald_base::kPi / 2, tn::Blocker::kWall, 0.05, &standing));
  const tn::PathDirection s = tn::choosePathDirection(cm, kFrame, squeezed, path, {5.0, 3.8, 0.0}, false);
  ASSERT_TRUE(s.ok) << s.error;
  EXPECT_TRUE(s.approach.reverse);
}
