// URDF through MuJoCo into one scene: names and prefixes kept, a free root, actuators per drive.
#include <gtest/gtest.h>

#include "test_scene.h"
#include "thorvald_sim/world.h"

namespace ts = thorvald_sim;

TEST(UrdfImport, KeepsPrefixedNamesAndFloatsTheRoot) {
  std::string root;
  const std::string mjcf = ts::urdfToMjcf(ts::referenceUrdf(thorvald_base::figure7Robot(), "r7"), &root);
  EXPECT_EQ(root, "r7/base_link");
  EXPECT_NE(mjcf.find("name=\"r7/steering5\""), std::string::npos);
  EXPECT_NE(mjcf.find("name=\"r7/wheel_link0\""), std::string::npos);
  EXPECT_NE(mjcf.find("type=\"free\""), std::string::npos);
}

TEST(UrdfImport, RejectsWhatIsNotARobot) {
  std::string root;
  EXPECT_THROW(ts::urdfToMjcf("not xml <", &root), ts::ModelError);
  EXPECT_THROW(ts::urdfToMjcf("<robot name=\"x\"/>", &root), ts::ModelError);
  EXPECT_THROW(ts::urdfToMjcf("<robot name=\"x\"><link name=\"a\"/><link name=\"b\"/></robot>", &root), ts::ModelError);
}

TEST(Scene, ActuatorsForEveryDriveOfEveryRobot) {
  ts::test::TestScene s(ts::makeFlatWorld(), {thorvald_base::figure7Robot(), ts::test::differential()});
  const mjModel* m = s.sim->model();
  EXPECT_EQ(m->nu, 6 * 2 + 2);  // figure 7: 6 steering + 6 wheels; differential: 2 wheels
  EXPECT_GE(s.sim->actuatorOfJoint("robot0/steering3"), 0);
  EXPECT_GE(s.sim->actuatorOfJoint("robot1/wheel1"), 0);
  EXPECT_EQ(s.sim->actuatorOfJoint("robot1/steering0"), -1);       // fixed drives have no steering
  EXPECT_EQ(s.sim->actuatorOfJoint("robot1/caster0_swivel"), -1);  // casters are passive
  EXPECT_FALSE(s.sim->setTarget(s.sim->actuatorOfJoint("robot0/wheel0"), NAN));
  EXPECT_EQ(s.sim->robotCount(), 2u);
}

TEST(Scene, ResetReturnsToTheSpawnPose) {
  ts::test::TestScene s(ts::makeFlatWorld(), {ts::test::fourWheelSteered()}, {{{1.0, 2.0, 0.5}}});
  const auto a = s.sim->robotState(0);
  EXPECT_NEAR(a.position.x(), 1.0, 1e-9);
  EXPECT_NEAR(a.yaw(), 0.5, 1e-9);
  s.drive(0, 1.0, 0, 0, 2.0);
  EXPECT_GT((s.sim->robotState(0).position - a.position).norm(), 0.5);
  s.sim->reset();
  EXPECT_NEAR((s.sim->robotState(0).position - a.position).norm(), 0.0, 1e-9);
  EXPECT_EQ(s.sim->time(), 0.0);
}

TEST(Scene, FourRobotsCommandedIndependently) {
  // Figure 11: robots of different configurations in one world, each doing its own thing.
  ts::test::TestScene s(ts::makeFlatWorld(),
                        {ts::test::fourWheelSteered(), thorvald_base::figure7Robot(), ts::test::differential(),
                         ts::test::fourWheelSteered()},
                        {{{0, 0, 0}}, {{0, 5, 0}}, {{0, 10, 0}}, {{0, 15, 0}}});
  s.run(1.0);  // settle on the wheels
  std::vector<ts::BodyState> start;
  for (int i = 0; i < 4; ++i) start.push_back(s.sim->robotState(i));
  const double end = s.t + 3.0;
  while (s.t < end) {
    s.command(0, 1.0, 0, 0);  // forward
    s.command(1, 0, 0.5, 0);  // crab left
    s.command(2, 0, 0, 0.5);  // turn in place
    // robot 3 gets nothing and must stay
    s.run(0.1);
  }
  auto moved = [&](int i) -> Eigen::Vector3d { return s.sim->robotState(i).position - start[i].position; };
  EXPECT_GT(moved(0).x(), 1.5);
  EXPECT_LT(std::fabs(moved(0).y()), 0.05);
  EXPECT_GT(moved(1).y(), 0.6);
  EXPECT_LT(std::fabs(moved(1).x()), 0.05);
  EXPECT_GT(std::remainder(s.sim->robotState(2).yaw() - start[2].yaw(), 2 * M_PI), 0.6);
  EXPECT_LT(moved(3).norm(), 0.005);
}
