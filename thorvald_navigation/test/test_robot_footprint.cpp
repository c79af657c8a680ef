// The footprint from a robot's URDF, and the greenhouse robot's frame turning beside a wall: the circle the planner
// plans with allows what the frame's polygon refuses, and the polygon fits where the circle round it would not.
#include <gtest/gtest.h>

#include "thorvald_base/angles.h"
#include "thorvald_navigation/goal_approach.h"
#include "thorvald_navigation/goal_runner.h"
#include "thorvald_navigation/robot_footprint.h"

namespace tn = thorvald_navigation;
using thorvald_base::Pose2D;

namespace {

// The greenhouse robot's parts as the generated URDF has them: drive wheels on base_link, the frame's top plate on a
// fixed joint (1.05 m x 0.92 m, 0.325 m behind base_link), a rear caster under it.
const char* const kGreenhouseUrdf = R"(<?xml version="1.0"?>
<robot name="greenhouse">
  <link name="base_link"/>
  <link name="wheel_link0"><collision><origin xyz="0 0 0" rpy="1.5708 0 0"/>
    <geometry><cylinder radius="0.175" length="0.06"/></geometry></collision></link>
  <joint name="wheel0" type="continuous"><parent link="base_link"/><child link="wheel_link0"/>
    <origin xyz="0 -0.2 0.175" rpy="0 0 0"/><axis xyz="0 1 0"/></joint>
  <link name="frame_top_plate"><collision><geometry><box size="1.05 0.92 0.004"/></geometry></collision></link>
  <joint name="frame_top_plate_joint" type="fixed"><parent link="base_link"/><child link="frame_top_plate"/>
    <origin xyz="-0.325 0 0.56" rpy="0 0 0"/></joint>
  <link name="caster"><collision><geometry><sphere radius="0.06"/></geometry></collision></link>
  <joint name="caster_joint" type="fixed"><parent link="frame_top_plate"/><child link="caster"/>
    <origin xyz="-0.45 0.15 -0.5" rpy="0 0 0"/></joint>
  <link name="outline_only_mesh"><collision><geometry><mesh filename="package://x/y.stl"/></geometry></collision>
  </link>
  <joint name="mesh_joint" type="fixed"><parent link="base_link"/><child link="outline_only_mesh"/></joint>
</robot>)";

/// Extent of a polygon along x and y [m].
Eigen::Vector4d bounds(const tn::Footprint& fp) {
  Eigen::Vector4d b(1e9, -1e9, 1e9, -1e9);
  for (const auto& p : fp.polygon)
    b = Eigen::Vector4d(std::min(b[0], p.x()), std::max(b[1], p.x()), std::min(b[2], p.y()), std::max(b[3], p.y()));
  return b;
}

}  // namespace

TEST(RobotFootprint, ConvexHullDropsInnerAndCollinearPoints) {
  const tn::Footprint fp =
      tn::convexHullFootprint({{0, 0}, {1, 0}, {0.5, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0.2, 0.3}, {1, 1}});
  ASSERT_EQ(fp.polygon.size(), 4u);
  EXPECT_EQ(fp.check(), "");
  EXPECT_TRUE(tn::convexHullFootprint({{0, 0}, {1, 1}}).check() != "");
  EXPECT_TRUE(tn::convexHullFootprint({{0, 0}, {1, 1}, {2, 2}}).check() != "");
}

TEST(RobotFootprint, FromUrdfTakesTheFrameWheelsAndCastersUnderBaseLink) {
  const tn::UrdfFootprint u = tn::footprintFromUrdf(kGreenhouseUrdf, "base_link");
  ASSERT_EQ(u.error, "");
  EXPECT_EQ(u.shapes, 3);
  ASSERT_EQ(u.skipped.size(), 1u);
  EXPECT_EQ(u.skipped[0], "outline_only_mesh");
  const Eigen::Vector4d b = bounds(u.footprint);
  // The frame's plate: x -0.85 .. 0.20, y -0.46 .. 0.46 (wheel and caster inside it).
  EXPECT_NEAR(b[0], -0.85, 1e-6);
  EXPECT_NEAR(b[1], 0.20, 1e-6);
  EXPECT_NEAR(b[2], -0.46, 1e-6);
  EXPECT_NEAR(b[3], 0.46, 1e-6);
  EXPECT_NEAR(u.footprint.halfWidth(), 0.46, 1e-6);
  // A tf_prefix on every name: base_link is found by its ending.
  std::string prefixed = kGreenhouseUrdf;
  for (std::size_t at = 0; (at = prefixed.find("\"base_link\"", at)) != std::string::npos; at += 10)
    prefixed.replace(at, 11, "\"r1/base_link\"");
  EXPECT_EQ(tn::footprintFromUrdf(prefixed, "base_link").error, "");
  EXPECT_NE(tn::footprintFromUrdf(kGreenhouseUrdf, "chassis").error.find("no link chassis"), std::string::npos);
  EXPECT_NE(tn::footprintFromUrdf("<robot", "base_link").error, "");
}

TEST(RobotFootprint, ACylinderStandingUpProjectsAsItsDisc) {
  const tn::UrdfFootprint u = tn::footprintFromUrdf(R"(<robot name="r"><link name="base_link"><collision>
      <origin xyz="1 0 0"/><geometry><cylinder radius="0.3" length="1"/></geometry></collision></link></robot>)",
                                                    "base_link");
  ASSERT_EQ(u.error, "");
  const Eigen::Vector4d b = bounds(u.footprint);
  EXPECT_NEAR(b[0], 0.7, 0.03);  // the 16-gon round the disc: within 1.5 % of its radius
  EXPECT_LE(b[0], 0.7);
  EXPECT_NEAR(b[3], 0.3, 0.03);
  EXPECT_GE(b[3], 0.3);
}

namespace {

// A floor 8 m x 5 m walled round (cells 5 cm; walls from y = 4.95 and below y = 0.05).
tn::Costmap walledFloor(double planning_radius_m) {
  thorvald_map::OccupancyGrid map{160, 100, 0.05, 0.0, 0.0, thorvald_map::kFree};
  for (int x = 0; x < map.width; ++x) map.at(x, 0) = map.at(x, map.height - 1) = thorvald_map::kOccupied;
  for (int y = 0; y < map.height; ++y) map.at(0, y) = map.at(map.width - 1, y) = thorvald_map::kOccupied;
  tn::CostmapParams p;
  p.planning_radius_m = planning_radius_m;
  p.inflation_radius_m = std::max(p.inflation_radius_m, planning_radius_m);
  return tn::Costmap(map, thorvald_map::OccupancyGrid{}, p);
}

const tn::Footprint kFrame = tn::rectangleFootprint(-0.85, 0.2, -0.46, 0.46);

}  // namespace

// At an outer target 0.8 m from the side wall the planning circle (the frame's half width) clears the wall, but the
// frame's rear, 0.97 m from base_link, sweeps over it when the robot turns away from the wall: the path must not
// start with that turn. The planners back along the path instead, and every pose of the drive keeps the frame clear.
TEST(RobotFootprint, ATurnTheCircleAllowsButTheFrameSweepsIsNotCommanded) {
  const tn::Costmap cm = walledFloor(kFrame.halfWidth());
  const Pose2D start{3.0, 4.15, 0.0}, goal{3.5, 2.55, 0.0};  // 0.8 m from the wall's face at y = 4.95
  // The circle allows standing and turning there; the frame's sweep to face the goal does not.
  const Eigen::Vector2i c = cm.geometry().cellOf({start.x, start.y});
  EXPECT_LT(cm.cost(c.x(), c.y()), tn::kInscribedCost);
  EXPECT_TRUE(tn::turnTouches(cm, kFrame, {start.x, start.y}, 0.0, -thorvald_base::kPi / 2, tn::Blocker::kWall));
  const tn::GoalPlanners p =
      tn::costmapPlanners([&]() -> const tn::Costmap& { return cm; }, kFrame, tn::PlannerParams{}, 0.3, 1.5, false);
  const tn::GoalPlan r = p.plan(start, goal);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.reverse);
  EXPECT_TRUE(r.then_to_goal);
  EXPECT_NEAR(r.first_target.x, 3.2, 1e-6);
  // Drive the plan as the follower would: the first turn, each leg with the footprint along it, the final turn.
  double heading = start.yaw;
  for (std::size_t i = 0; i + 1 < r.path.size(); ++i) {
    const Eigen::Vector2d d = r.path[i + 1] - r.path[i];
    const double way = thorvald_base::normalizeAngle(std::atan2(d.y(), d.x()) + thorvald_base::kPi);
    EXPECT_FALSE(tn::turnTouches(cm, kFrame, r.path[i], heading, way, tn::Blocker::kWall)) << i;
    heading = way;
    for (double s = 0.0; s <= 1.0; s += 0.05) {
      const Eigen::Vector2d q = r.path[i] + s * d;
      EXPECT_EQ(cm.footprintBlocker({q.x(), q.y(), heading}, kFrame), tn::Blocker::kNone) << i << " " << s;
    }
  }
  EXPECT_FALSE(tn::turnTouches(cm, kFrame, r.path.back(), heading, goal.yaw, tn::Blocker::kWall));
}

// A strip 1.5 m wide between two walls: a goal facing the other way needs a half turn, whose sweep (0.97 m round
// base_link) meets a wall 0.75 m away wherever the robot turns: no direction clears. The plan is driven forward as the
// planner made it (as before the sweep), with the turn that meets the wall as its warning.
TEST(RobotFootprint, APlanNoDirectionClearsIsDrivenForwardWithAWarning) {
  thorvald_map::OccupancyGrid map{160, 100, 0.05, 0.0, 0.0, thorvald_map::kFree};
  for (int x = 0; x < map.width; ++x)
    for (int y = 0; y < map.height; ++y)
      if (x == 0 || y <= 68 || x == map.width - 1 || y == map.height - 1) map.at(x, y) = thorvald_map::kOccupied;
  tn::CostmapParams cp;
  cp.planning_radius_m = kFrame.halfWidth();
  const tn::Costmap strip(map, thorvald_map::OccupancyGrid{}, cp);
  const Pose2D start{6.0, 4.2, 0.0}, goal{3.0, 4.2, thorvald_base::kPi};
  EXPECT_EQ(strip.footprintBlocker(goal, kFrame), tn::Blocker::kNone);
  const tn::GoalPlanners p =
      tn::costmapPlanners([&]() -> const tn::Costmap& { return strip; }, kFrame, tn::PlannerParams{}, 0.3, 1.5, false);
  const tn::GoalPlan r = p.plan(start, goal);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_FALSE(r.reverse);
  EXPECT_FALSE(r.then_to_goal);
  EXPECT_NE(r.warning.find("turn"), std::string::npos) << r.warning;
  EXPECT_NE(r.warning.find("wall"), std::string::npos) << r.warning;
}

// A passage 1.1 m wide: the frame (0.92 m wide) driven along it fits, though the circle round it (0.97 m radius)
// would not; the planners plan through it with the frame's half width and the path keeps the polygon clear.
TEST(RobotFootprint, ANarrowPassageTheCircleRefusesTheFrameFits) {
  thorvald_map::OccupancyGrid map{160, 100, 0.05, 0.0, 0.0, thorvald_map::kFree};
  for (int x = 0; x < map.width; ++x)
    for (int y = 0; y < map.height; ++y) {
      const bool border = x == 0 || y == 0 || x == map.width - 1 || y == map.height - 1;
      const bool passage_walls = x >= 50 && x <= 110 && (y <= 38 || y >= 61);  // free y 1.95 .. 3.05
      if (border || passage_walls) map.at(x, y) = thorvald_map::kOccupied;
    }
  tn::CostmapParams cp;
  cp.planning_radius_m = kFrame.halfWidth() + 0.02;
  const tn::Costmap cm(map, thorvald_map::OccupancyGrid{}, cp);
  tn::CostmapParams circle = cp;
  circle.planning_radius_m = std::sqrt(0.85 * 0.85 + 0.46 * 0.46);
  const tn::Costmap round(map, thorvald_map::OccupancyGrid{}, circle);
  const Pose2D start{1.5, 2.5, 0.0}, goal{7.0, 2.5, 0.0};
  EXPECT_FALSE(tn::planPath(round, {start.x, start.y}, {goal.x, goal.y}, tn::PlannerParams{}).ok);
  const tn::GoalPlanners p =
      tn::costmapPlanners([&]() -> const tn::Costmap& { return cm; }, kFrame, tn::PlannerParams{}, 0.3, 1.5, false);
  const tn::GoalPlan r = p.plan(start, goal);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_FALSE(r.reverse);
  for (std::size_t i = 0; i + 1 < r.path.size(); ++i) {
    const Eigen::Vector2d d = r.path[i + 1] - r.path[i];
    const double yaw = std::atan2(d.y(), d.x());
    for (double s = 0.0; s <= 1.0; s += 0.05) {
      const Eigen::Vector2d q = r.path[i] + s * d;
      EXPECT_EQ(cm.footprintBlocker({q.x(), q.y(), yaw}, kFrame), tn::Blocker::kNone) << i << " " << s;
    }
  }
}

// The greenhouse's two outer rail sets: from a target 0.75 m from one side wall to the next target 1.6 m over, 0.81 m
// from the other side wall, both facing the rows. Forward, the first turn swings the rear into the first wall; backing
// all the way puts the rear into the second wall at the final approach's start. The robot backs to where it can turn
// in the open, turns there and drives on forward; every motion keeps the frame clear.
TEST(RobotFootprint, BetweenTwoWallsTheRobotBacksToWhereItCanTurn) {
  thorvald_map::OccupancyGrid map{160, 100, 0.05, 0.0, 0.0, thorvald_map::kFree};
  for (int x = 0; x < map.width; ++x)
    for (int y = 0; y < map.height; ++y)
      if (x == 0 || x == map.width - 1 || y == 0 || y >= 64) map.at(x, y) = thorvald_map::kOccupied;
  tn::CostmapParams cp;
  cp.planning_radius_m = kFrame.halfWidth();
  const tn::Costmap cm(map, thorvald_map::OccupancyGrid{}, cp);
  const Pose2D start{4.0, 2.45, 0.0}, goal{4.0, 0.86, 0.0};  // walls' faces at y = 3.2 and y = 0.05
  const tn::GoalPlanners p =
      tn::costmapPlanners([&]() -> const tn::Costmap& { return cm; }, kFrame, tn::PlannerParams{}, 0.3, 1.5, false);
  const tn::GoalPlan r = p.plan(start, goal);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.reverse);
  ASSERT_TRUE(r.then_to_goal);
  ASSERT_GE(r.second_leg.size(), 2u);
  EXPECT_LT((r.second_leg.back() - Eigen::Vector2d(goal.x, goal.y)).norm(), 1e-9);
  // The turn point leaves room for the frame's rear round it (1.0 m) on both sides.
  EXPECT_GT(r.first_target.y, 0.05 + 0.97);
  EXPECT_LT(r.first_target.y, 3.2 - 0.97);
  // Drive it: back along the first leg, turn, forward along the second, final turn; the frame clear all the way.
  double heading = start.yaw;
  const auto drive = [&](const std::vector<Eigen::Vector2d>& leg, bool reverse) {
    for (std::size_t i = 0; i + 1 < leg.size(); ++i) {
      const Eigen::Vector2d d = leg[i + 1] - leg[i];
      if (d.norm() < 1e-9) continue;
      const double way = thorvald_base::normalizeAngle(std::atan2(d.y(), d.x()) + (reverse ? thorvald_base::kPi : 0.0));
      EXPECT_FALSE(tn::turnTouches(cm, kFrame, leg[i], heading, way, tn::Blocker::kWall)) << i;
      heading = way;
      const Eigen::Vector2d q = leg[i + 1];
      EXPECT_EQ(cm.footprintBlocker({q.x(), q.y(), heading}, kFrame), tn::Blocker::kNone) << i;
    }
  };
  drive(r.path, true);
  drive(r.second_leg, false);
  EXPECT_FALSE(tn::turnTouches(cm, kFrame, r.second_leg.back(), heading, goal.yaw, tn::Blocker::kWall));
}
