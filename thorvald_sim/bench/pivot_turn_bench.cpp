// A robot reverses, stops and turns on the spot, in MuJoCo with base_driver's code in process and encoders from the
// physics (as the missions run it): how long the turn takes against the commanded time, and per wheel the
// commanded and measured speeds, the caster swivel angles and every contact that is not a wheel on the floor.
//
//   rosrun thorvald_sim pivot_turn_bench --config ROBOT.yaml --urdf ROBOT.urdf [--world greenhouse ...]
//
// The URDF comes from thorvald_model's urdf_generator (with the robot's extras), e.g. for the greenhouse robot:
//   rosrun thorvald_model urdf_generator --config $(rospack find thorvald_bringup)/config/greenhouse_rail_robot.yaml \
//     --extras $(rospack find thorvald_bringup)/config/greenhouse_frame.urdf --tf-prefix '' --robot-name gh > gh.urdf
#include <thorvald_base/robot_config.h>

#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "thorvald_sim/drive_loop.h"
#include "thorvald_sim/mjcf_compiler.h"
#include "thorvald_sim/scene.h"
#include "thorvald_sim/simulation.h"
#include "thorvald_sim/world.h"

namespace ts = thorvald_sim;

namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string name(const mjModel* m, mjtObj type, int id) {
  const char* n = mj_id2name(m, type, id);
  return n ? n : "#" + std::to_string(id);
}

// Contacts other than a wheel geom on the floor: "robot body -> world geom (normal force N)".
std::string contacts(const mjModel* m, const mjData* d, const std::vector<std::string>& floor_names) {
  std::map<std::string, double> force;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    int g_robot = c.geom1, g_world = c.geom2;
    if (m->geom_bodyid[g_robot] == 0) std::swap(g_robot, g_world);
    const std::string body = name(m, mjOBJ_BODY, m->geom_bodyid[g_robot]);
    const std::string other = name(m, mjOBJ_GEOM, g_world);
    bool floor = false;
    for (const auto& f : floor_names) floor = floor || other.rfind(f, 0) == 0;
    const bool wheel = body.find("wheel") != std::string::npos;
    if (floor && wheel) continue;
    mjtNum f6[6];
    mj_contactForce(m, d, i, f6);
    force[body + "->" + other] += f6[0];
  }
  std::string out;
  for (const auto& [k, f] : force) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), " (%.0f N)", f);
    out += (out.empty() ? "" : ", ") + k + buf;
  }
  return out.empty() ? "-" : out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string config_file, urdf_file, world = "flat";
  double x = 0, y = 0, yaw = 0, reverse_m = 1.0, reverse_speed = 0.3, turn_rad = -M_PI, rate = 0.6, acc = 1.0;
  double wall_margin = 1.2, passive_damping = -1, timeout_factor = 4.0;
  int rail_sets = 3;
  bool quiet = false;
  CLI::App app{"A robot reverses, then turns on the spot; turn time and per-wheel log"};
  app.add_option("--config", config_file, "robot file (thorvald_bringup/config/*.yaml)")->required();
  app.add_option("--urdf", urdf_file, "its URDF (urdf_generator with the robot's extras)")->required();
  app.add_option("--world", world, "flat or greenhouse")->check(CLI::IsMember({"flat", "greenhouse"}));
  app.add_option("--x", x, "start pose of base_link [m]");
  app.add_option("--y", y, "[m]");
  app.add_option("--yaw", yaw, "[rad]");
  app.add_option("--reverse", reverse_m, "distance reversed before the turn [m]")->check(CLI::Range(0.0, 20.0));
  app.add_option("--reverse-speed", reverse_speed, "[m/s]")->check(CLI::Range(0.05, 1.0));
  app.add_option("--turn", turn_rad, "turn on the spot [rad], negative clockwise")->check(CLI::Range(-6.3, 6.3));
  app.add_option("--rate", rate, "turn rate limit [rad/s] (headland_navigator's max_vel_theta)")
      ->check(CLI::Range(0.05, 2.0));
  app.add_option("--acc", acc, "turn acceleration limit [rad/s^2]")->check(CLI::Range(0.1, 10.0));
  app.add_option("--rail-sets", rail_sets, "greenhouse: rail sets")->check(CLI::Range(1, 20));
  app.add_option("--wall-margin", wall_margin, "greenhouse: outer sets' centres to the side walls [m]")
      ->check(CLI::Range(0.5, 5.0));
  app.add_option("--passive-damping", passive_damping, "override SceneOptions::passive_damping [N m s/rad]");
  app.add_option("--timeout-factor", timeout_factor, "give up after this many commanded turn times")
      ->check(CLI::Range(1.5, 100.0));
  app.add_flag("--quiet", quiet, "only the summary");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;

  try {
    const auto config = thorvald_base::loadRobotConfigFile(config_file);
    ts::RobotSpawn spawn;
    spawn.x = x, spawn.y = y, spawn.yaw = yaw, spawn.z = 0.01;
    spawn.mjcf = ts::urdfToMjcf(readFile(urdf_file), &spawn.root_link);
    ts::SceneOptions options;
    options.sphere_wheels = world == "flat";
    if (passive_damping >= 0) options.passive_damping = passive_damping;
    ts::WorldDescription w;
    if (world == "greenhouse") {
      ts::GreenhouseParams p;
      p.rail_sets = rail_sets;
      p.wall_margin_m = wall_margin;
      p.rail_length_m = 4.0;
      w = ts::makeGreenhouseWorld(p, nullptr);
    } else {
      w = ts::makeFlatWorld();
    }
    ts::Simulation sim(ts::composeScene(w, {spawn}, options), {spawn});
    ts::DrivenRobot robot(sim, config, "", {}, ts::EncoderSource::kPhysics);
    const mjModel* m = sim.model();
    const mjData* d = sim.data();
    std::vector<std::string> wheels, casters;
    for (int j = 0; j < m->njnt; ++j) {
      const std::string n = name(m, mjOBJ_JOINT, j);
      const auto role = ts::jointRole(n);
      if (role == ts::JointRole::kWheel) wheels.push_back(n);
      if (n.find("_swivel") != std::string::npos) casters.push_back(n);
    }
    const std::vector<std::string> floor_names = {"floor", "headland", "ground"};
    const int steps = static_cast<int>(std::lround(0.02 / sim.timestep()));
    double t = 0;
    auto cycle = [&](double vx, double wz) {
      robot.command({vx, 0, wz}, t);
      robot.control(t);
      sim.step(steps);
      t += 0.02;
    };
    auto log = [&](const char* phase, double wz_cmd) {
      if (quiet) return;
      const auto s = sim.robotState(0);
      std::printf("%6.2f %-8s x %6.3f y %6.3f yaw %7.3f wz %6.3f/%6.3f |", t, phase, s.position.x(), s.position.y(),
                  s.yaw(), wz_cmd, s.angular_body.z());
      for (const auto& wj : wheels) {
        double v = 0;
        sim.jointState(wj, nullptr, &v);
        std::printf(" %s %6.2f/%6.2f", wj.c_str(), sim.target(sim.actuatorOfJoint(wj)), v);
      }
      std::printf(" | swivel");
      for (const auto& c : casters) {
        double q = 0;
        sim.jointState(c, &q, nullptr);
        std::printf(" %6.1f", std::remainder(q, 2 * M_PI) * 180 / M_PI);
      }
      std::printf(" | %s\n", contacts(m, d, floor_names).c_str());
    };
    for (int i = 0; i < 50; ++i) cycle(0, 0);
    // Reverse at reverse_speed (ramped at 0.5 m/s^2), then stop.
    const auto start = sim.robotState(0);
    double v = 0;
    int k = 0;
    while ((sim.robotState(0).position - start.position).norm() < reverse_m && t < 60) {
      v = std::max(-reverse_speed, v - 0.5 * 0.02);
      cycle(v, 0);
      if (++k % 25 == 0) log("reverse", 0);
    }
    for (; v < 0; v = std::min(0.0, v + 0.5 * 0.02)) cycle(v, 0);
    for (int i = 0; i < 25; ++i) cycle(0, 0);
    log("stopped", 0);
    // Turn on the spot: rate-limited, acceleration-limited, proportional near the end (like the navigator).
    const double yaw0 = sim.robotState(0).yaw();
    const double commanded_s = std::fabs(turn_rad) / rate + rate / acc;
    const double t0 = t;
    double wz = 0, done_t = -1;
    double min_rate_ratio = 1e9, prev = yaw0, turned = 0;
    k = 0;
    while (t - t0 < timeout_factor * commanded_s) {
      const double now = sim.robotState(0).yaw();  // unwrapped: turned since the start of the turn
      turned += std::remainder(now - prev, 2 * M_PI);
      prev = now;
      const double err = turn_rad - turned;
      if (std::fabs(err) < 0.015) {
        done_t = t - t0;
        break;
      }
      const double want = std::clamp(2.0 * err, -rate, rate);
      wz = std::clamp(want, wz - acc * 0.02, wz + acc * 0.02);
      cycle(0, wz);
      if (std::fabs(want) >= rate * 0.999 && t - t0 > rate / acc + 0.5)
        min_rate_ratio = std::min(min_rate_ratio, sim.robotState(0).angular_body.z() / want);
      if (++k % 25 == 0) log("turn", wz);
    }
    log(done_t >= 0 ? "done" : "timeout", wz);
    const double turn_s = done_t >= 0 ? done_t : t - t0;
    std::printf("turn of %.2f rad at %.2f rad/s: commanded %.2f s, took %.2f s%s; min yaw rate / commanded %.2f\n",
                turn_rad, rate, commanded_s, turn_s, done_t >= 0 ? "" : " (NOT completed)", min_rate_ratio);
    std::printf(
        "RESULT {\"world\": \"%s\", \"turn_rad\": %.3f, \"commanded_s\": %.2f, \"turn_s\": %.2f, \"completed\": %s, "
        "\"min_rate_ratio\": %.3f, \"divergences\": %zu}\n",
        world.c_str(), turn_rad, commanded_s, turn_s, done_t >= 0 ? "true" : "false", min_rate_ratio,
        static_cast<size_t>(sim.divergences()));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pivot_turn_bench: %s\n", e.what());
    return 1;
  }
}
