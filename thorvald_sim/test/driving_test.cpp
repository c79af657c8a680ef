// Robots driven by base_driver's joint simulator move by contact physics: straight, turning in place and crab,
// with odometry from joint states and ground truth agreeing on flat ground.
#include <gtest/gtest.h>

#include <cmath>

#include "test_scene.h"
#include "thorvald_sim/world.h"

using thorvald_sim::makeFlatWorld;
using thorvald_sim::test::TestScene;

namespace {

struct Motion {
  double dx, dy, dyaw;  // in the start frame
};

Motion truthMotion(const TestScene& s, size_t i, const thorvald_sim::BodyState& start) {
  const auto now = s.sim->robotState(i);
  const double c = std::cos(start.yaw()), sn = std::sin(start.yaw());
  const double wx = now.position.x() - start.position.x(), wy = now.position.y() - start.position.y();
  return {c * wx + sn * wy, -sn * wx + c * wy, std::remainder(now.yaw() - start.yaw(), 2 * M_PI)};
}

// Settles the robot on its wheels, resets odometry, drives, stops and returns truth and odometry.
void driveAndCompare(const thorvald_base::RobotConfig& robot, double vx, double vy, double wz, double seconds,
                     double pos_tol_m, double yaw_tol_rad) {
  TestScene s(makeFlatWorld(), {robot});
  s.drive(0, 0, 0, 0, 1.0);
  s.robots[0]->driver().resetOdometry();
  const auto start = s.sim->robotState(0);
  s.drive(0, vx, vy, wz, seconds);
  s.drive(0, 0, 0, 0, 1.5);
  const Motion m = truthMotion(s, 0, start);
  const auto& odom = s.robots[0]->driver().odometry().pose();
  // The commanded motion (constant twist for `seconds`), ignoring acceleration and steering time: a loose check
  // that the robot did move as asked.
  const double th = wz * seconds;
  const double ex = std::fabs(wz) < 1e-9 ? vx * seconds : (vx * std::sin(th) + vy * (std::cos(th) - 1)) / wz;
  const double ey = std::fabs(wz) < 1e-9 ? vy * seconds : (vx * (1 - std::cos(th)) + vy * std::sin(th)) / wz;
  const double len = std::hypot(vx, vy) * seconds;
  EXPECT_NEAR(m.dx, ex, 0.25 * len + 0.1);
  EXPECT_NEAR(m.dy, ey, 0.25 * len + 0.1);
  EXPECT_NEAR(m.dyaw, std::remainder(wz * seconds, 2 * M_PI), 0.25 * std::fabs(wz * seconds) + 0.05);
  // The real check: ground truth and odometry from joint states agree (no slip on flat ground).
  EXPECT_NEAR(odom.x, m.dx, pos_tol_m);
  EXPECT_NEAR(odom.y, m.dy, pos_tol_m);
  EXPECT_NEAR(std::remainder(odom.yaw - m.dyaw, 2 * M_PI), 0.0, yaw_tol_rad);
  EXPECT_EQ(s.sim->divergences(), 0u);
}

}  // namespace

// Tolerances: 2 % of the distance plus 2 cm, 0.03 rad.
TEST(Driving, FourWheelSteeredStraight) {
  driveAndCompare(thorvald_sim::test::fourWheelSteered(), 1.0, 0, 0, 4.0, 0.1, 0.03);
}
TEST(Driving, FourWheelSteeredTurnInPlace) {
  driveAndCompare(thorvald_sim::test::fourWheelSteered(), 0, 0, 0.5, 3.0, 0.05, 0.05);
}
TEST(Driving, FourWheelSteeredCrab) {
  driveAndCompare(thorvald_sim::test::fourWheelSteered(), 0, 0.6, 0, 4.0, 0.07, 0.03);
}
TEST(Driving, Figure7RobotArc) { driveAndCompare(thorvald_base::figure7Robot(), 0.8, 0.0, 0.3, 4.0, 0.1, 0.05); }
TEST(Driving, DifferentialStraightAndTurn) {
  driveAndCompare(thorvald_sim::test::differential(), 0.8, 0, 0, 4.0, 0.08, 0.03);
  driveAndCompare(thorvald_sim::test::differential(), 0, 0, 0.5, 3.0, 0.05, 0.05);
}

TEST(Driving, NoJitterAtRest) {
  TestScene s(makeFlatWorld(), {thorvald_sim::test::fourWheelSteered()});
  s.drive(0, 0, 0, 0, 2.0);
  const auto a = s.sim->robotState(0);
  s.drive(0, 0, 0, 0, 20.0);
  const auto b = s.sim->robotState(0);
  EXPECT_LT((b.position - a.position).norm(), 1e-3);  // less than 1 mm of creep in 20 s
  EXPECT_LT(b.linear_body.norm(), 1e-3);
  EXPECT_NEAR(b.position.z(), 0.0, 0.01);  // base_link on the ground
}

TEST(Driving, DisagreeingWheelsSlip) {
  // One wheel runs 20 % fast: the robot goes where the other three take it and that wheel slips, so its own
  // rolling disagrees with the body's motion; the body still moves about as commanded. With the drive torque
  // limit (SceneOptions::wheel_torque_limit) no wheel can be forced to slip on this ground; without it, one can.
  thorvald_sim::SceneOptions unlimited;
  unlimited.wheel_torque_limit = false;
  TestScene s(makeFlatWorld(), {thorvald_sim::test::fourWheelSteered()}, {}, unlimited);
  s.drive(0, 0, 0, 0, 1.0);
  const auto start = s.sim->robotState(0);
  const int act = s.sim->actuatorOfJoint("wheel0");
  ASSERT_GE(act, 0);
  const double end = s.t + 3.0;
  while (s.t < end) {
    s.command(0, 1.0, 0, 0);
    for (auto& r : s.robots) r->control(s.t);
    s.sim->setTarget(act, s.sim->target(act) * 1.2);
    s.sim->step(10);
    s.t += 0.02;
  }
  const auto now = s.sim->robotState(0);
  const double dist = (now.position - start.position).norm();
  double w0 = 0, w1 = 0;
  s.sim->jointState("wheel0", &w0, nullptr);
  s.sim->jointState("wheel1", &w1, nullptr);
  EXPECT_GT(w0 * 0.2, 1.1 * w1 * 0.2);  // the fast wheel turned more ...
  EXPECT_LT(dist, 1.08 * w1 * 0.2);     // ... than the body travelled
}
