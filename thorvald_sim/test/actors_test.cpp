// Actors follow their scripts, the sensors see them, and robot body contacts are reported (wheels on the floor not).
#include <gtest/gtest.h>

#include <cmath>

#include "test_scene.h"
#include "thorvald_sim/actors.h"
#include "thorvald_sim/contacts.h"
#include "thorvald_sim/ray_caster.h"

namespace ts = thorvald_sim;

namespace {

ts::ActorSpec walker() {
  ts::ActorSpec s;
  s.name = "worker1";
  // Walks 4 m along x in 4 s, stands 2 s, walks 2 m along y in 2 s.
  s.path = {{0, 0, 1}, {4, 0, 5}, {4, 0, 7}, {4, 2, 9}};
  return s;
}

ts::ActorSpec wanderer(unsigned seed) {
  ts::ActorSpec s;
  s.name = "wanderer";
  s.random_walk = true;
  s.region[0] = -5, s.region[1] = -1, s.region[2] = 0, s.region[3] = 10;
  s.speed_mps = 1.2;
  s.seed = seed;
  return s;
}

/// The flat floor with a crate 2 m ahead of the origin, plus `extra` bodies.
ts::WorldDescription floorWithCrate(const std::string& extra = "") {
  ts::WorldDescription w = ts::makeFlatWorld(20.0);
  w.worldbody += "<geom name=\"crate0\" type=\"box\" pos=\"2.2 0 0.3\" size=\"0.2 0.8 0.3\"/>\n" + extra;
  return w;
}

}  // namespace

TEST(Actors, ScriptedPathPositionAtTime) {
  ts::ActorScripts a({walker()});
  auto at = [&](double t) { return a.poseAt(0, t); };
  EXPECT_NEAR(at(0.0).x, 0.0, 1e-12);  // stands at the first waypoint before its time
  EXPECT_NEAR(at(3.0).x, 2.0, 1e-12);  // halfway along the first leg
  EXPECT_NEAR(at(3.0).yaw, 0.0, 1e-12);
  EXPECT_NEAR(at(6.0).x, 4.0, 1e-12);  // standing, still facing +x
  EXPECT_NEAR(at(6.0).yaw, 0.0, 1e-12);
  EXPECT_NEAR(at(8.0).y, 1.0, 1e-12);
  EXPECT_NEAR(at(8.0).yaw, M_PI / 2, 1e-12);
  EXPECT_NEAR(at(100.0).y, 2.0, 1e-12);  // stays at the last point
  ts::ActorSpec loop = walker();
  loop.loop = true;
  ts::ActorScripts l({loop});
  EXPECT_NEAR(l.poseAt(0, 3.0 + 8.0).x, 2.0, 1e-9);  // period 8 s (first to last waypoint)
}

// A person does not walk into a machine: walking along x towards a robot standing in the way at x = 3 (a body of
// 0.5 m radius), the walker (radius 0.25) stands 0.3 m short of it, walks on once the robot has gone, and its script
// runs late by the time it waited; a step away from a robot is never held.
TEST(Actors, ActorsStandShortOfARobotInTheirWayAndWalkOnWhenItHasGone) {
  ts::ActorScripts a({walker()});
  ts::ActorClocks clocks(a, 0.3);
  const ts::ActorClocks::RobotGap robot = [](double x, double y) { return std::hypot(x - 3.0, y) - 0.5; };
  double x = 0.0;
  for (double t = 0.0; t <= 8.0 + 1e-9; t += 0.01) x = clocks.advance(t, robot)[0].x;
  EXPECT_NEAR(x, 3.0 - 0.5 - 0.25 - 0.3, 0.02) << "stands the clearance short of the robot";
  EXPECT_GT(clocks.waited(0), 5.0);
  for (double t = 8.01; t <= 20.0 + 1e-9; t += 0.01) x = clocks.advance(t, nullptr)[0].x;  // the robot has gone
  const ts::ActorPose end = clocks.advance(20.0, nullptr)[0];
  EXPECT_NEAR(end.x, 4.0, 1e-9);
  EXPECT_NEAR(end.y, 2.0, 1e-9);                    // finished its path, later than scripted
  EXPECT_NEAR(clocks.waited(0), 8.0 - 2.95, 0.05);  // reached 1.95 m at t = 2.95 (1 m/s from t = 1), stood to t = 8
  // Walking away from a robot right behind it is not held.
  ts::ActorClocks away(a, 0.3);
  const ts::ActorClocks::RobotGap behind = [](double x, double y) { return std::hypot(x + 0.6, y) - 0.3; };
  for (double t = 0.0; t <= 5.0 + 1e-9; t += 0.01) x = away.advance(t, behind)[0].x;
  EXPECT_NEAR(x, 4.0, 1e-9);
  EXPECT_EQ(away.waited(0), 0.0);
}

// A person kept waiting by a robot that does not move (it stopped because of them) gives way after give_way_s: steps
// back along their path for step_back_s, then comes on again and stands short of the robot once more.
TEST(Actors, APersonKeptWaitingStepsBackTheWayTheyCame) {
  ts::ActorScripts a({walker()});
  ts::ActorClocks clocks(a, 0.3, 4.0, 1.5);
  const ts::ActorClocks::RobotGap robot = [](double x, double y) { return std::hypot(x - 3.0, y) - 0.5; };
  const double stand_x = 3.0 - 0.5 - 0.25 - 0.3;
  double x = 0.0, min_after_wait = 1e9;
  for (double t = 0.0; t <= 2.95 + 4.0 - 0.05; t += 0.01) x = clocks.advance(t, robot)[0].x;
  EXPECT_NEAR(x, stand_x, 0.02) << "stood short of the robot until give_way_s had passed";
  for (double t = 6.91; t <= 8.5; t += 0.01) min_after_wait = std::min(min_after_wait, clocks.advance(t, robot)[0].x);
  EXPECT_NEAR(min_after_wait, stand_x - 1.5, 0.05) << "stepped back 1.5 s of its path (1 m/s)";
  for (double t = 8.51; t <= 12.0; t += 0.01) x = clocks.advance(t, robot)[0].x;
  EXPECT_NEAR(x, stand_x, 0.02) << "came on again and stands short of the robot";
  // Without give_way it stands for good.
  ts::ActorClocks patient(a, 0.3);
  double lowest = 1e9;
  for (double t = 0.0; t <= 20.0; t += 0.01) {
    x = patient.advance(t, robot)[0].x;
    if (t > 3.0) lowest = std::min(lowest, x);
  }
  EXPECT_NEAR(lowest, stand_x, 0.02);
}

// A triggered actor stands at the start of its script until a robot's body comes within the trigger's radius of its
// point, then runs the script from its beginning, once: the robot leaving does not stop it.
TEST(Actors, ATriggeredPersonStartsWhenARobotReachesThePointAndNotBefore) {
  ts::ActorSpec s = walker();  // path from t = 1: 4 m along x in 4 s, ...
  s.path.front().t = 0.0;      // ... now from t = 0: 4 m in 5 s, 0.8 m/s
  s.trigger_x = 10.0, s.trigger_y = 0.0, s.trigger_radius_m = 0.1;
  ts::ActorScripts a({s});
  ts::ActorClocks clocks(a, 0.3);
  double robot_x = 20.0;  // a robot of 0.5 m radius driving towards the trigger point along x from beyond it
  const ts::ActorClocks::RobotGap robot = [&](double x, double y) { return std::hypot(x - robot_x, y) - 0.5; };
  double t = 0.0;
  for (; robot_x > 10.62; t += 0.01, robot_x -= 0.005) {
    EXPECT_EQ(clocks.advance(t, robot)[0].x, 0.0) << "stands at the start before the robot comes near, t " << t;
    EXPECT_FALSE(clocks.running(0));
  }
  robot_x = 10.61;  // its body 0.11 m from the point: not yet
  EXPECT_EQ(clocks.advance(t, robot)[0].x, 0.0);
  EXPECT_FALSE(clocks.running(0));
  robot_x = 10.59;  // 0.09 m: set off
  clocks.advance(t, robot);
  EXPECT_TRUE(clocks.running(0));
  const double t0 = t;
  robot_x = 100.0;  // the robot goes away: the script runs on
  double x = 0.0;
  for (t = t0; t <= t0 + 2.0 + 1e-9; t += 0.01) x = clocks.advance(t, robot)[0].x;
  EXPECT_NEAR(x, 1.6, 0.02) << "walked 2 s of its path since the trigger, from its start";
  // Without robots it never starts; a bad trigger is refused.
  ts::ActorClocks alone(a, 0.3);
  for (t = 0.0; t <= 10.0; t += 0.5) EXPECT_EQ(alone.advance(t, nullptr)[0].x, 0.0);
  s.trigger_radius_m = -1.0;
  EXPECT_THROW(ts::ActorScripts({s}), std::invalid_argument);
}

TEST(Actors, RandomWalkStaysInItsRegionAndRepeatsWithItsSeed) {
  ts::ActorScripts a({wanderer(5)}), b({wanderer(5)}), c({wanderer(6)});
  double travelled = 0.0, differs = 0.0;
  ts::ActorPose last = a.poseAt(0, 0.0);
  for (double t = 0.0; t < 600.0; t += 0.5) {
    const ts::ActorPose p = a.poseAt(0, t), q = b.poseAt(0, t), r = c.poseAt(0, t);
    EXPECT_GE(p.x, -5.0);
    EXPECT_LE(p.x, -1.0);
    EXPECT_GE(p.y, 0.0);
    EXPECT_LE(p.y, 10.0);
    EXPECT_EQ(p.x, q.x);
    EXPECT_EQ(p.y, q.y);
    differs = std::max(differs, std::hypot(p.x - r.x, p.y - r.y));
    travelled += std::hypot(p.x - last.x, p.y - last.y);
    last = p;
  }
  EXPECT_GT(travelled, 200.0);  // it walks (1.2 m/s with 2 s pauses)
  EXPECT_LE(travelled, 1.2 * 600.0 + 1e-6);
  EXPECT_GT(differs, 1.0);
}

TEST(Actors, BadScriptsAreRefusedNamingTheActor) {
  ts::ActorSpec s = walker();
  s.path[2].t = 4.0;  // back in time
  try {
    ts::ActorScripts a({s});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("worker1"), std::string::npos);
  }
  ts::ActorSpec w = wanderer(1);
  w.region[1] = -6;  // x_max below x_min
  EXPECT_THROW(ts::ActorScripts({w}), std::invalid_argument);
  EXPECT_THROW(ts::ActorScripts({walker(), walker()}), std::invalid_argument);  // one name twice
}

TEST(Actors, MocapBodiesMoveAndTheLidarSeesThem) {
  ts::ActorScripts actors({walker()});
  ts::WorldDescription w = ts::makeFlatWorld(20.0);
  w.worldbody += ts::actorBodies(actors, [](double, double) { return 0.0; });
  ts::test::StaticWorld world(w);
  const int body = mj_name2id(world.model.get(), mjOBJ_BODY, ts::actorBodyName("worker1").c_str());
  ASSERT_GE(body, 0);
  const int mocap = world.model->body_mocapid[body];
  ASSERT_GE(mocap, 0);
  const ts::ActorPose p = actors.poseAt(0, 3.0);  // (2, 0)
  world.data->mocap_pos[3 * mocap] = p.x, world.data->mocap_pos[3 * mocap + 1] = p.y;
  mj_forward(world.model.get(), world.data.get());
  ts::RayCaster caster(world.model.get(), world.data.get(), -1);
  const Eigen::Vector3d origin(-3.0, 0.0, 1.0), dir(1.0, 0.0, 0.0);
  caster.prepare(origin, 30.0, dir, M_PI);
  int geom = -1;
  EXPECT_NEAR(caster.cast(origin, dir, &geom), 5.0 - 0.25, 1e-6);  // the person's front at x = 1.75
  EXPECT_EQ(mj_id2name(world.model.get(), mjOBJ_GEOM, geom), ts::actorBodyName("worker1"));
}

// The actors' gap to a robot: from a point on the floor to the nearest of its geoms' boxes, turned with the body.
TEST(Contacts, FloorGapToABodysGeoms) {
  ts::WorldDescription w = ts::makeFlatWorld(20.0);
  w.worldbody +=
      "<body name=\"robot\" pos=\"1 2 0.3\" quat=\"0.70710678 0 0 0.70710678\"><geom name=\"plate\" type=\"box\" "
      "size=\"0.5 0.2 0.1\"/></body>\n";
  ts::test::StaticWorld s(w);
  const int root = mj_name2id(s.model.get(), mjOBJ_BODY, "robot");
  ASSERT_GE(root, 0);
  // Turned 90 degrees: the plate reaches 0.2 m along x and 0.5 m along y from (1, 2).
  EXPECT_NEAR(ts::floorGapToBodies(s.model.get(), s.data.get(), {root}, 2.0, 2.0), 0.8, 1e-6);
  EXPECT_NEAR(ts::floorGapToBodies(s.model.get(), s.data.get(), {root}, 1.0, 3.0), 0.5, 1e-6);
  EXPECT_NEAR(ts::floorGapToBodies(s.model.get(), s.data.get(), {root}, 1.1, 2.3), 0.0, 1e-9);  // over it
  EXPECT_TRUE(std::isinf(ts::floorGapToBodies(s.model.get(), s.data.get(), {}, 2.0, 2.0)));
}

TEST(Contacts, CrateContactIsReportedWheelsOnTheFloorAreNot) {
  ts::test::TestScene s(floorWithCrate(), {ts::test::fourWheelSteered()});
  ts::ContactMonitor monitor(s.sim->model(), {{s.sim->robot(0).root_body, "r1"}});
  s.run(0.5);  // settle on the wheels
  EXPECT_TRUE(monitor.update(s.sim->data()).empty());
  std::vector<ts::ContactEvent> events;
  for (int i = 0; i < 250 && events.empty(); ++i) {  // up to 5 s at 0.5 m/s: the frame reaches the crate
    s.command(0, 0.5, 0, 0);
    s.run(0.02);
    for (const auto& e : monitor.update(s.sim->data())) events.push_back(e);
  }
  ASSERT_FALSE(events.empty()) << "never touched the crate";
  EXPECT_TRUE(events[0].start);
  EXPECT_EQ(events[0].other, "crate0");
  EXPECT_EQ(events[0].robot, "r1");
  EXPECT_NEAR(events[0].position.x(), 2.0, 0.05);             // on the crate's face
  for (const auto& e : events) EXPECT_EQ(e.other, "crate0");  // the frame and perhaps a wheel: all on the crate
  for (int i = 0; i < 100; ++i) {                             // back off: the contact ends
    s.command(0, -0.5, 0, 0);
    s.run(0.02);
    for (const auto& e : monitor.update(s.sim->data())) events.push_back(e);
  }
  ASSERT_GE(events.size(), 2u);
  EXPECT_FALSE(events.back().start);
  EXPECT_EQ(monitor.active(), 0u);
}

TEST(Contacts, AnActorWalkingIntoARobotIsReported) {
  ts::ActorSpec s;
  s.name = "worker2";
  s.path = {{3.0, 0.0, 0.0}, {0.0, 0.0, 3.0}};  // walks through where the robot stands
  ts::ActorScripts actors({s});
  ts::WorldDescription w = ts::makeFlatWorld(20.0);
  w.worldbody += ts::actorBodies(actors, [](double, double) { return 0.0; });
  ts::test::TestScene scene(w, {ts::test::fourWheelSteered()});
  ts::ContactMonitor monitor(scene.sim->model(), {{scene.sim->robot(0).root_body, "r1"}});
  const int mocap = scene.sim->model()->body_mocapid[mj_name2id(scene.sim->model(), mjOBJ_BODY, "actor_worker2")];
  std::vector<ts::ContactEvent> events;
  for (int i = 0; i < 150; ++i) {
    const ts::ActorPose p = actors.poseAt(0, scene.t);
    scene.sim->mutableData()->mocap_pos[3 * mocap] = p.x;
    scene.run(0.02);
    for (const auto& e : monitor.update(scene.sim->data())) events.push_back(e);
  }
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0].other, "actor_worker2");
}

TEST(Contacts, RobotsCollideWithEachOtherAndTheContactIsReportedOnce) {
  ts::test::TestScene s(ts::makeFlatWorld(20.0), {ts::test::fourWheelSteered(), ts::test::fourWheelSteered()},
                        {{{0.0, 0.0, 0.0}}, {{2.6, 0.0, 0.0}}});
  ts::ContactMonitor monitor(s.sim->model(),
                             {{s.sim->robot(0).root_body, "robot0"}, {s.sim->robot(1).root_body, "robot1"}});
  std::vector<ts::ContactEvent> events;
  for (int i = 0; i < 250 && events.empty(); ++i) {  // robot0 drives into robot1
    s.command(0, 0.5, 0, 0);
    s.run(0.02);
    for (const auto& e : monitor.update(s.sim->data())) events.push_back(e);
  }
  ASSERT_FALSE(events.empty()) << "robot0 drove through robot1";
  EXPECT_EQ(events[0].robot, "robot0");
  EXPECT_EQ(events[0].other.rfind("robot1/", 0), 0u) << events[0].other;
  EXPECT_LT(s.sim->robotState(0).position.x(), 2.6 - 1.0);  // stopped short of robot1's centre
}
