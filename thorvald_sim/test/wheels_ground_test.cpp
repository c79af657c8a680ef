// Wheels and ground: slip per surface (dry concrete, wet concrete, loose soil), the suspension modules' passive
// hinges keeping every wheel on uneven ground, and the default (ideal) scene unchanged byte for byte.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "test_scene.h"

namespace ts = thorvald_sim;

namespace {

/// FNV-1a over bytes.
void hashInto(uint64_t* h, const void* data, size_t n) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) *h = (*h ^ bytes[i]) * 0x100000001b3ull;
}
constexpr uint64_t kFnvStart = 0xcbf29ce484222325ull;

/// Slip and sinkage of the four-wheel robot when every wheel's servo is stepped from rest to the same speed (past
/// base_driver's ramps and without the drive torque limit: the same servo torque on every surface).
struct Traction {
  double slip = 0.0;    ///< 1 - ground distance / wheel surface distance over the first second
  double base_z = 0.0;  ///< base_link's height at rest [m]
};

Traction tractionOn(ts::Ground ground) {
  ts::SceneOptions o;
  o.ground = ground;
  o.wheel_torque_limit = false;
  const auto robot = ts::test::fourWheelSteered();
  ts::test::TestScene s(ts::makeFlatWorld(), {robot}, {}, o);
  s.sim->step(500);  // settle
  Traction t;
  t.base_z = s.sim->robotState(0).position.z();
  std::vector<double> start(robot.drives.size());
  for (size_t i = 0; i < robot.drives.size(); ++i) {
    s.sim->jointState("wheel" + std::to_string(i), &start[i], nullptr);
    s.sim->setTarget(s.sim->actuatorOfJoint("wheel" + std::to_string(i)), 10.0);
  }
  const double x0 = s.sim->robotState(0).position.x();
  s.sim->step(500);
  double wheel_m = 0.0;
  for (size_t i = 0; i < robot.drives.size(); ++i) {
    double q = 0.0;
    s.sim->jointState("wheel" + std::to_string(i), &q, nullptr);
    wheel_m += (q - start[i]) * robot.drives[i].r_wheel / robot.drives.size();
  }
  t.slip = 1.0 - (s.sim->robotState(0).position.x() - x0) / wheel_m;
  return t;
}

/// How many of the robot's wheel geoms touch the world now.
int wheelsInContact(const ts::Simulation& sim, const std::vector<std::string>& wheel_bodies) {
  const mjModel* m = sim.model();
  const mjData* d = sim.data();
  int n = 0;
  for (const auto& name : wheel_bodies) {
    const int b = mj_name2id(m, mjOBJ_BODY, name.c_str());
    bool touching = false;
    for (int c = 0; c < d->ncon && !touching; ++c)
      touching = m->geom_bodyid[d->contact[c].geom1] == b || m->geom_bodyid[d->contact[c].geom2] == b;
    n += touching ? 1 : 0;
  }
  return n;
}

/// The fewest wheels of the four-wheel robot on the ground while its drive 1 (front right) rolls over a bump of
/// `height` m; `travel` rad of suspension on every drive (0: rigid).
int fewestWheelsOverBump(double travel, double height) {
  auto robot = ts::test::fourWheelSteered();
  ts::WorldDescription w = ts::makeFlatWorld();
  w.worldbody += ts::bumpGeom("bump", 2.0, -0.6, height, 0.5);
  ts::RobotSpawn spawn;
  spawn.mjcf = ts::urdfToMjcf(ts::referenceUrdf(robot, ""), &spawn.root_link);
  spawn.z = 0.01;
  if (travel > 0) spawn.suspension_rad.assign(robot.drives.size(), travel);
  ts::Simulation sim(ts::composeScene(w, {spawn}, ts::SceneOptions()), {spawn});
  ts::DrivenRobot driven(sim, robot, "");
  std::vector<std::string> wheels;
  for (size_t i = 0; i < robot.drives.size(); ++i) wheels.push_back("wheel_link" + std::to_string(i));
  int fewest = 4;
  const int steps = static_cast<int>(std::lround(0.02 / sim.timestep()));
  for (double t = 0.0; t < 9.0; t += 0.02) {
    driven.command({t < 1.0 ? 0.0 : 0.5, 0.0, 0.0}, t);
    driven.control(t);
    sim.step(steps);
    if (t > 1.0) fewest = std::min(fewest, wheelsInContact(sim, wheels));
  }
  EXPECT_GT(sim.robotState(0).position.x(), 3.5) << "the robot did not cross the bump";
  return fewest;
}

}  // namespace

TEST(Ground, NamesRoundTripAndUnknownIsRefused) {
  for (auto g : {ts::Ground::kDryConcrete, ts::Ground::kWetConcrete, ts::Ground::kLooseSoil})
    EXPECT_EQ(ts::groundFromName(ts::groundName(g)), g);
  EXPECT_FALSE(ts::groundFromName("ice"));
  EXPECT_EQ(ts::groundOfWorld("greenhouse", ts::Realism::kDatasheet), ts::Ground::kWetConcrete);
  EXPECT_EQ(ts::groundOfWorld("cotton_row", ts::Realism::kDatasheet), ts::Ground::kLooseSoil);
  EXPECT_EQ(ts::groundOfWorld("greenhouse", ts::Realism::kIdeal), ts::Ground::kDryConcrete);
}

TEST(Ground, WetConcreteSlipsMoreThanDryAndLooseSoilSinksAndSlipsMost) {
  const Traction dry = tractionOn(ts::Ground::kDryConcrete), wet = tractionOn(ts::Ground::kWetConcrete),
                 soil = tractionOn(ts::Ground::kLooseSoil);
  std::printf("slip dry %.4f wet %.4f soil %.4f; base z dry %.4f wet %.4f soil %.4f\n", dry.slip, wet.slip, soil.slip,
              dry.base_z, wet.base_z, soil.base_z);
  EXPECT_GT(wet.slip, dry.slip + 0.01);
  EXPECT_GT(soil.slip, wet.slip);
  EXPECT_LT(soil.base_z, dry.base_z - 0.005) << "loose soil does not let the wheels sink";
}

TEST(Suspension, KeepsEveryWheelOnTheGroundOverABumpThatLiftsARigidRobotsWheel) {
  const int rigid = fewestWheelsOverBump(0.0, 0.08), sprung = fewestWheelsOverBump(0.35, 0.08);
  std::printf("fewest wheels in contact over the bump: rigid %d, with suspension %d\n", rigid, sprung);
  EXPECT_LT(rigid, 4);
  EXPECT_EQ(sprung, 4);
}

// The expected hashes were taken from the code before surfaces and suspension were added (thorvald_sim at c0bf3f6);
// the scene's hash again at e029489, which gave each robot its own collision bits (robots collide with each other),
// a change of the scene text that is not the ground's. The run's hash is still c0bf3f6's.
TEST(IdealGround, SceneAndShortRunAreTheSameAsBefore) {
  const auto robot = ts::test::fourWheelSteered();
  ts::RobotSpawn spawn;
  spawn.mjcf = ts::urdfToMjcf(ts::referenceUrdf(robot, ""), &spawn.root_link);
  spawn.z = 0.01;
  const std::string xml = ts::composeScene(ts::makeFlatWorld(), {spawn}, ts::SceneOptions());
  uint64_t scene = kFnvStart;
  hashInto(&scene, xml.data(), xml.size());
  EXPECT_EQ(scene, 0x3c3b7682bcc53e3aull) << std::hex << scene;

  ts::test::TestScene s(ts::makeFlatWorld(), {robot});
  uint64_t run = kFnvStart;
  for (int k = 0; k < 10; ++k) {
    s.drive(0, 0.8, 0.1, 0.2, 0.2);
    const mjData* d = s.sim->data();
    hashInto(&run, d->qpos, sizeof(mjtNum) * s.sim->model()->nq);
  }
  EXPECT_EQ(run, 0x3f2251498643be26ull) << std::hex << run;
}

TEST(Suspension, TravelOfADriveIsItsNearestCornersSuspAngle) {
  auto robot = ts::test::fourWheelSteered();
  robot.corners.clear();
  EXPECT_TRUE(ts::suspensionOfDrives(robot).empty()) << "a robot without corners stays rigid";
  for (const auto& d : robot.drives) {
    thorvald_base::CornerConfig c;
    c.x = d.x + 0.05, c.y = d.y;
    c.susp_ang = d.index == 2 ? -0.35 : 0.0;
    robot.corners.push_back(c);
  }
  EXPECT_EQ(ts::suspensionOfDrives(robot), (std::vector<double>{0.0, 0.0, 0.35, 0.0}));
  for (auto& c : robot.corners) c.susp_ang = 0.0;
  EXPECT_TRUE(ts::suspensionOfDrives(robot).empty()) << "corners without susp_ang keep the robot rigid";
}
