// The greenhouse robot (thorvald_bringup's robot file and frame extras through thorvald_model's urdf_generator) on
// the greenhouse's headland floor, wheels as their cylinders, encoders from the physics (as the UV mission runs):
// after reversing its casters have swivelled round, and a turn on the spot still completes close to the commanded
// time both ways; near a side wall the same turn is stopped by the frame against the wall (the contact is what
// stalls it, not the casters).
#include <gtest/gtest.h>
#include <thorvald_base/robot_config.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "thorvald_sim/drive_loop.h"
#include "thorvald_sim/world.h"

namespace ts = thorvald_sim;

namespace {

#if defined(URDF_GENERATOR) && defined(BRINGUP_CONFIG_DIR)
std::string greenhouseUrdf() {
  const std::string dir = BRINGUP_CONFIG_DIR;
  const std::string cmd = std::string(URDF_GENERATOR) + " --config '" + dir +
                          "/greenhouse_rail_robot.yaml' --extras '" + dir +
                          "/greenhouse_frame.urdf' --tf-prefix '' --robot-name greenhouse";
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof(buf), p)) > 0) out.append(buf, n);
    if (pclose(p) != 0) out.clear();
  }
  return out;
}
#endif

struct TurnResult {
  bool completed = false;
  double seconds = 0.0;        ///< simulated time of the turn (until within 0.015 rad, or the timeout)
  double commanded_s = 0.0;    ///< the commanded profile's duration
  double turned_rad = 0.0;     ///< at the end
  double caster_swivel[2]{};   ///< swivel angles after reversing [rad]
  bool frame_touched = false;  ///< a frame part (not a wheel) touched the world during the turn
};

// Spawns the robot at (x, 0, yaw 0), in front of the first of two rail sets (the second 1.6 m to its left), on the
// headland of a greenhouse whose side walls are `wall_margin` from the outer sets' centre lines, reverses `reverse_m`
// at 0.3 m/s, stops, then turns `turn_rad` on the spot like the headland navigator (0.6 rad/s, 1 rad/s^2, proportional
// at the end).
TurnResult reverseAndTurn(const std::string& urdf, double wall_margin, double x, double reverse_m, double turn_rad) {
  const auto config =
      thorvald_base::loadRobotConfigFile(std::string(BRINGUP_CONFIG_DIR) + "/greenhouse_rail_robot.yaml");
  ts::GreenhouseParams gp;
  gp.rail_sets = 2;
  gp.rail_length_m = 4.0;
  gp.wall_margin_m = wall_margin;
  ts::RobotSpawn spawn;
  spawn.x = x;
  spawn.z = 0.01;
  spawn.mjcf = ts::urdfToMjcf(urdf, &spawn.root_link);
  ts::SceneOptions options;
  options.sphere_wheels = false;  // the pipes stand beside the floor wheels (as the node runs this robot)
  ts::Simulation sim(ts::composeScene(ts::makeGreenhouseWorld(gp, nullptr), {spawn}, options), {spawn});
  ts::DrivenRobot robot(sim, config, "", {}, ts::EncoderSource::kPhysics);
  const int steps = static_cast<int>(std::lround(0.02 / sim.timestep()));
  double t = 0;
  auto cycle = [&](double vx, double wz) {
    robot.command({vx, 0, wz}, t);
    robot.control(t);
    sim.step(steps);
    t += 0.02;
  };
  for (int i = 0; i < 50; ++i) cycle(0, 0);
  const auto start = sim.robotState(0);
  double v = 0;
  while ((sim.robotState(0).position - start.position).norm() < reverse_m && t < 30)
    cycle(v = std::max(-0.3, v - 0.01), 0);
  for (; v < 0; v = std::min(0.0, v + 0.01)) cycle(v, 0);
  for (int i = 0; i < 25; ++i) cycle(0, 0);
  TurnResult r;
  sim.jointState("caster0_swivel", &r.caster_swivel[0], nullptr);
  sim.jointState("caster1_swivel", &r.caster_swivel[1], nullptr);
  const double rate = 0.6, acc = 1.0;
  r.commanded_s = std::fabs(turn_rad) / rate + rate / acc;
  const mjModel* m = sim.model();
  const mjData* d = sim.data();
  double prev = sim.robotState(0).yaw(), wz = 0;
  const double t0 = t;
  while (t - t0 < 3.0 * r.commanded_s) {
    const double now = sim.robotState(0).yaw();
    r.turned_rad += std::remainder(now - prev, 2 * M_PI);
    prev = now;
    const double err = turn_rad - r.turned_rad;
    if (std::fabs(err) < 0.015) {
      r.completed = true;
      break;
    }
    wz = std::clamp(std::clamp(2.0 * err, -rate, rate), wz - acc * 0.02, wz + acc * 0.02);
    cycle(0, wz);
    for (int i = 0; i < d->ncon; ++i) {
      const int b1 = m->geom_bodyid[d->contact[i].geom1], b2 = m->geom_bodyid[d->contact[i].geom2];
      const int robot_body = b1 == 0 ? b2 : b1;
      const char* n = mj_id2name(m, mjOBJ_BODY, robot_body);
      if ((b1 == 0) != (b2 == 0) && n && std::string(n).rfind("frame_", 0) == 0) r.frame_touched = true;
    }
  }
  r.seconds = t - t0;
  std::printf(
      "wall margin %.2f m, turn %.2f rad: %s in %.2f s (commanded %.2f s), turned %.3f rad, casters after "
      "reversing %.0f / %.0f deg, frame touched: %s\n",
      wall_margin, turn_rad, r.completed ? "completed" : "NOT completed", r.seconds, r.commanded_s, r.turned_rad,
      r.caster_swivel[0] * 180 / M_PI, r.caster_swivel[1] * 180 / M_PI, r.frame_touched ? "yes" : "no");
  EXPECT_EQ(sim.divergences(), 0u);
  return r;
}

}  // namespace

TEST(GreenhouseRobotTurn, OnTheSpotAfterReversingCompletesNearTheCommandedTime) {
#if defined(URDF_GENERATOR) && defined(BRINGUP_CONFIG_DIR)
  const std::string urdf = greenhouseUrdf();
  ASSERT_FALSE(urdf.empty()) << "urdf_generator failed for the greenhouse robot";
  for (const double turn : {-M_PI, M_PI}) {
    SCOPED_TRACE(turn);
    // Headland floor, 1.6 m to the side walls: the 0.97 m the frame's rear corners sweep round the front axle fit.
    const TurnResult r = reverseAndTurn(urdf, 1.6, -0.3, 1.0, turn);
    // Reversing swivelled the casters round (their wheels now lead the swivel axis) ...
    for (const double s : r.caster_swivel) EXPECT_GT(std::fabs(std::remainder(s, 2 * M_PI)), 2.5);
    // ... and the turn still takes at most 1.4 x the commanded profile (about 1.15 x: the casters swivel round).
    EXPECT_TRUE(r.completed);
    EXPECT_LT(r.seconds, 1.4 * r.commanded_s);
    EXPECT_FALSE(r.frame_touched);
  }
#else
  GTEST_SKIP() << "needs thorvald_model's urdf_generator and thorvald_bringup's robot files in the build";
#endif
}

TEST(GreenhouseRobotTurn, FrameAgainstTheSideWallStopsTheTurn) {
#if defined(URDF_GENERATOR) && defined(BRINGUP_CONFIG_DIR)
  const std::string urdf = greenhouseUrdf();
  ASSERT_FALSE(urdf.empty()) << "urdf_generator failed for the greenhouse robot";
  // The UV mission's greenhouse puts the side walls 0.8 m from the outer sets' centres: turning towards the wall
  // (counter-clockwise here, the wall on the right), the frame's rear corner (0.97 m from the front axle) meets the
  // wall after about 0.5 rad and the turn stalls: a drive wheel at about a fifth of its commanded speed.
  const TurnResult r = reverseAndTurn(urdf, 0.8, -0.3, 0.54, M_PI / 2);
  EXPECT_FALSE(r.completed);
  EXPECT_TRUE(r.frame_touched);
  EXPECT_LT(r.turned_rad, 0.8);
  // The other way round the rear swings away from the wall.
  const TurnResult cw = reverseAndTurn(urdf, 0.8, -0.3, 0.54, -M_PI / 2);
  EXPECT_TRUE(cw.completed);
  EXPECT_LT(cw.seconds, 1.4 * cw.commanded_s);
  EXPECT_FALSE(cw.frame_touched);
#else
  GTEST_SKIP() << "needs thorvald_model's urdf_generator and thorvald_bringup's robot files in the build";
#endif
}
