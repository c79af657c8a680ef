// Encoders from the physics against base_driver's joint simulator: a robot driving into a wall.
#include <gtest/gtest.h>

#include <cmath>

#include "test_scene.h"
#include "thorvald_sim/geom_writer.h"
#include "thorvald_sim/physics_drive.h"
#include "thorvald_sim/world.h"

namespace ts = thorvald_sim;

namespace {

// The flat world with a concrete wall across x = wall_x.
ts::WorldDescription wallWorld(double wall_x) {
  ts::WorldDescription w = ts::makeFlatWorld();
  ts::GeomWriter g;
  g.box("wall", {wall_x + 0.1, 0, 0.75}, {0.1, 4.0, 0.75}, ts::colours::kWall);
  w.worldbody += g.str();
  return w;
}

struct WallRun {
  double odom_at_4s = 0, odom_at_8s = 0;  ///< odometry distance [m]
  double truth_x_at_4s = 0, truth_x_at_8s = 0;
  double max_wheel_speed_late = 0;  ///< |wheel speed| in the feedback during the last 2 s [rad/s]
  double commanded_wheel_speed = 0;
};

// The 4WS robot drives forward at 0.5 m/s for 8 s towards a wall 1.5 m ahead of its centre.
WallRun driveIntoWall(ts::EncoderSource encoders) {
  const auto robot = ts::test::fourWheelSteered();
  ts::RobotSpawn spawn;
  spawn.mjcf = ts::urdfToMjcf(ts::referenceUrdf(robot, ""), &spawn.root_link);
  spawn.z = 0.01;
  ts::Simulation sim(ts::composeScene(wallWorld(1.5), {spawn}, ts::SceneOptions()), {spawn});
  ts::DrivenRobot driven(sim, robot, "", {}, encoders);
  const int steps = static_cast<int>(std::lround(0.02 / sim.timestep()));
  WallRun r;
  double t = 0.0;
  for (int k = 0; k < 400; ++k, t += 0.02) {
    driven.command({0.5, 0.0, 0.0}, t);
    driven.control(t);
    sim.step(steps);
    if (k == 199)
      r.odom_at_4s = driven.driver().odometry().distance(), r.truth_x_at_4s = sim.robotState(0).position.x();
    if (k >= 300)
      for (const auto& f : driven.driver().feedback())
        r.max_wheel_speed_late = std::max(r.max_wheel_speed_late, std::fabs(f.wheel_speed_radps));
  }
  r.odom_at_8s = driven.driver().odometry().distance();
  r.truth_x_at_8s = sim.robotState(0).position.x();
  r.commanded_wheel_speed = 0.5 / robot.drives[0].r_wheel;
  return r;
}

}  // namespace

TEST(PhysicsEncoders, WheelsStallAtAWallAndOdometryStops) {
  const WallRun r = driveIntoWall(ts::EncoderSource::kPhysics);
  // The body is stopped by the wall well before 4 s (1.5 m minus half the robot's length at 0.5 m/s).
  EXPECT_NEAR(r.truth_x_at_8s, r.truth_x_at_4s, 0.01);
  EXPECT_LT(r.truth_x_at_8s, 1.5);
  // The wheels stall: their encoders read (nearly) zero while 2.5 rad/s is commanded, so odometry stops too.
  EXPECT_LT(r.max_wheel_speed_late, 0.05 * r.commanded_wheel_speed);
  EXPECT_LT(r.odom_at_8s - r.odom_at_4s, 0.02);
}

TEST(PhysicsEncoders, JointSimulatorOdometryKeepsGrowingAtAWall) {
  // The papers' design: odometry integrates the joint simulator, which knows nothing of the wall.
  const WallRun r = driveIntoWall(ts::EncoderSource::kJointSimulator);
  EXPECT_NEAR(r.truth_x_at_8s, r.truth_x_at_4s, 0.01);
  EXPECT_NEAR(r.odom_at_8s - r.odom_at_4s, 0.5 * 4.0, 0.05);
  EXPECT_NEAR(r.max_wheel_speed_late, r.commanded_wheel_speed, 0.05 * r.commanded_wheel_speed);
}

TEST(PhysicsEncoders, OpenGroundOdometryAgreesWithTruth) {
  const auto robot = ts::test::fourWheelSteered();
  ts::RobotSpawn spawn;
  spawn.mjcf = ts::urdfToMjcf(ts::referenceUrdf(robot, ""), &spawn.root_link);
  spawn.z = 0.01;
  ts::Simulation sim(ts::composeScene(ts::makeFlatWorld(), {spawn}, ts::SceneOptions()), {spawn});
  ts::DrivenRobot driven(sim, robot, "", {}, ts::EncoderSource::kPhysics);
  const int steps = static_cast<int>(std::lround(0.02 / sim.timestep()));
  double t = 0.0;
  for (int k = 0; k < 250; ++k, t += 0.02) {  // 5 s: 3 s straight, 2 s crab
    driven.command(k < 150 ? thorvald_base::Twist2D{0.5, 0.0, 0.0} : thorvald_base::Twist2D{0.0, 0.3, 0.0}, t);
    driven.control(t);
    sim.step(steps);
  }
  const auto truth = sim.robotState(0);
  const auto& odom = driven.driver().odometry().pose();
  const double dist = truth.position.head<2>().norm();
  EXPECT_GT(dist, 1.5);
  EXPECT_NEAR(odom.x, truth.position.x(), 0.02 + 0.02 * dist);
  EXPECT_NEAR(odom.y, truth.position.y(), 0.02 + 0.02 * dist);
  EXPECT_NEAR(odom.yaw, truth.yaw(), 0.03);
}

TEST(PhysicsDrive, ReadingsAreQuantisedLikeTheEncoders) {
  thorvald_base::DriveConfig c = ts::test::fourWheelSteered().drives[0];
  c.prp_gr_rt = 42, c.prp_enc_ppr = 1024, c.str_gr_rt = 42.8571429, c.str_enc_ppr = 1024;
  ts::JointMeasurement m{1.2345678, 2.0001, 0.3000123, 0.1};
  const auto f = ts::encoderReading(c, m);
  // Speed in whole motor rpm: 2.0001 rad/s * 42 * 30 / pi = 802.2 rpm -> 802 rpm.
  EXPECT_NEAR(f.wheel_speed_radps, 802 * M_PI / 30.0 / 42.0, 1e-12);
  const double wheel_count = 2 * M_PI / (4 * 1024 * 42.0), steer_count = 2 * M_PI / (4 * 1024 * 42.8571429);
  EXPECT_NEAR(std::remainder(f.wheel_position_rad, wheel_count), 0.0, 1e-12);
  EXPECT_NEAR(f.wheel_position_rad, m.wheel_position_rad, 0.5 * wheel_count + 1e-12);
  EXPECT_NEAR(std::remainder(f.steering_rad, steer_count), 0.0, 1e-12);
  EXPECT_NEAR(f.steering_rad, m.steering_rad, 0.5 * steer_count + 1e-12);
  EXPECT_TRUE(f.valid);
}

TEST(PhysicsDrive, OfflineUntilMeasuredAndWhenMeasurementsStop) {
  const thorvald_base::DriveConfig c = ts::test::fourWheelSteered().drives[0];
  ts::PhysicsDrive d(c, 0.5);
  d.update(1.0);
  EXPECT_FALSE(d.status().online);
  EXPECT_FALSE(d.feedback().valid);
  EXPECT_TRUE(d.measure({0, 1, 0, 0}, 1.0));
  d.update(1.2);
  EXPECT_TRUE(d.status().online);
  d.update(1.6);
  EXPECT_FALSE(d.status().online);
  EXPECT_FALSE(d.measure({0, std::nan(""), 0, 0}, 1.6));  // refused, still offline
  EXPECT_FALSE(d.status().online);
  // Steering commands are held within the robot file's limit.
  d.setCommand({1.0, 10.0});
  EXPECT_NEAR(d.command().steering_rad, c.str_lim, 1e-12);
}
