// Long-run stability of the MuJoCo simulation: the Figure 7 robot (reference URDF) drives the paper's 77 s loop
// again and again, resting 3 s after each, for a number of simulated hours. Reports physics divergences, whether
// every state stayed finite, how far the body drifts while it stands still (jitter at rest), how far its height
// strays from where it settled, and the real-time factor.
//
//   rosrun thorvald_sim stability_bench [--hours H]   (default 1)
#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <thorvald_base/testing/odometry_trial.h>

#include "thorvald_sim/drive_loop.h"
#include "thorvald_sim/testing/reference_urdf.h"
#include "thorvald_sim/world.h"

using namespace thorvald_sim;

int main(int argc, char** argv) {
  double hours = 1.0;
  CLI::App app{"Long-run stability of the MuJoCo simulation: the Figure 7 robot drives the paper's loop for hours"};
  app.add_option("--hours", hours, "simulated hours")->check(CLI::Range(1e-3, 1000.0));
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress shows when piped
  const thorvald_base::RobotConfig robot = thorvald_base::figure7Robot();
  RobotSpawn spawn;
  spawn.z = 0.01;
  spawn.mjcf = urdfToMjcf(referenceUrdf(robot, ""), &spawn.root_link);
  Simulation sim(composeScene(makeFlatWorld(), {spawn}, SceneOptions()), {spawn});
  DrivenRobot driven(sim, robot, "");

  const double dt = 0.02;
  const int steps = static_cast<int>(std::lround(dt / sim.timestep()));
  double t = 0.0;
  auto cycle = [&](const thorvald_base::Twist2D& cmd) {
    driven.command(cmd, t);
    driven.control(t);
    sim.step(steps);
    t += dt;
  };
  for (int i = 0; i < 100; ++i) cycle({});  // settle on the wheels
  const double settled_z = sim.robotState(0).position.z();

  auto plan = thorvald_base::paperLoop();
  plan.push_back({3.0, {}});
  bool finite = true;
  double max_rest_drift_m = 0.0, max_height_dev_m = 0.0, distance_m = 0.0;
  int loops = 0;
  const auto wall0 = std::chrono::steady_clock::now();
  while (t < hours * 3600.0) {
    for (const auto& seg : plan) {
      const double end = t + seg.duration_s;
      const bool rest = seg.twist.isZero();
      Eigen::Vector3d last = sim.robotState(0).position, rest_from = last;
      int k = 0;
      while (t < end - 1e-9) {
        cycle(seg.twist);
        const Eigen::Vector3d p = sim.robotState(0).position;
        finite = finite && p.allFinite();
        distance_m += (p - last).head<2>().norm();
        last = p;
        max_height_dev_m = std::max(max_height_dev_m, std::fabs(p.z() - settled_z));
        // At rest: after 1 s of stopping, the body should not move at all.
        if (rest && ++k == 50) rest_from = p;
        if (rest && k > 50) max_rest_drift_m = std::max(max_rest_drift_m, (p - rest_from).head<2>().norm());
      }
    }
    ++loops;
    if (loops % 10 == 0)
      std::printf("[%5.1f %%] %d loops, %.2f simulated hours, divergences %lu\n", 100.0 * t / (hours * 3600.0), loops,
                  t / 3600, sim.divergences());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::printf("Figure 7 robot, %d loops of 77 s + 3 s rest, %.2f simulated hours, %.1f km driven\n", loops, t / 3600,
              distance_m / 1000);
  std::printf("%-34s %12lu\n", "physics divergences (resets)", sim.divergences());
  std::printf("%-34s %12s\n", "all states finite", finite ? "yes" : "NO");
  std::printf("%-34s %12.3f\n", "max drift at rest [mm]", 1000 * max_rest_drift_m);
  std::printf("%-34s %12.3f\n", "max height deviation [mm]", 1000 * max_height_dev_m);
  std::printf("%-34s %12.1f\n", "real-time factor", t / wall);
  std::printf(
      "RESULT {\"sim_hours\": %.2f, \"divergences\": %lu, \"finite\": %s, \"max_rest_drift_mm\": %.3f, "
      "\"max_height_dev_mm\": %.3f, \"rtf\": %.1f}\n",
      t / 3600, sim.divergences(), finite ? "true" : "false", 1000 * max_rest_drift_m, 1000 * max_height_dev_m,
      t / wall);
  return finite && sim.divergences() == 0 ? 0 : 1;
}
