// Cost of one base_driver cycle (commands + simulated drives + odometry) against the number of drives.
// Usage: cycle_bench [--cycles N]   (--help for details)
#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "thorvald_base/base_driver.h"
#include "thorvald_base/testing/odometry_trial.h"
#include "thorvald_base/simulated_drive.h"
#include "thorvald_base/standard_calculator.h"

namespace {

thorvald_base::RobotConfig ringRobot(int n) {
  // n drives on a ring of 1 m radius: every drive steers to its own angle when the robot turns.
  thorvald_base::RobotConfig r = thorvald_base::figure7Robot();
  const auto prototype = r.drives[0];
  r.drives.clear();
  for (int i = 0; i < n; ++i) {
    auto d = prototype;
    d.index = i;
    d.node = i + 1;
    d.x = n == 1 ? 0.5 : std::cos(2 * M_PI * i / n);
    d.y = n == 1 ? 0.0 : std::sin(2 * M_PI * i / n);
    r.drives.push_back(d);
  }
  if (n == 1) {
    // One steered drive needs passive wheels off its axle to determine the motion (Figure 10 d, g).
    for (double y : {-0.35, 0.35}) {
      thorvald_base::PassiveWheelConfig p;
      p.x = -0.5;
      p.y = y;
      r.passive_wheels.push_back(p);
    }
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  int cycles = 20000;
  CLI::App app("Cost of one base_driver cycle against the number of drives", "cycle_bench");
  app.add_option("--cycles", cycles, "cycles per robot and estimator")
      ->check(CLI::Range(1, 100000000))
      ->capture_default_str();
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  std::printf("%-8s %16s %16s %18s\n", "drives", "ls cycle [us]", "paper cycle [us]", "ls per drive [us]");
  double us9 = 0;
  for (int n : {1, 2, 4, 9, 16, 32}) {
    double us[2];
    int k = 0;
    for (const char* estimator : {"least_squares", "random_pairs"}) {
      const auto robot = ringRobot(n);
      std::vector<std::unique_ptr<thorvald_base::MotorDrive>> drives;
      for (const auto& d : robot.drives) drives.push_back(std::make_unique<thorvald_base::SimulatedDrive>(d));
      thorvald_base::BaseDriverOptions o;
      o.calculator.estimator = estimator;
      thorvald_base::BaseDriver driver(robot, std::make_unique<thorvald_base::StandardCalculator>(), std::move(drives),
                                       {}, o);
      const auto start = std::chrono::steady_clock::now();
      for (int c = 0; c < cycles; ++c) {
        const double t = c * 0.02;
        driver.setCommand({0.5 * std::cos(t), 0.3 * std::sin(0.5 * t), 0.4 * std::sin(0.3 * t)}, t);
        driver.update(t);
      }
      const double elapsed =
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
      us[k++] = elapsed / cycles;
    }
    if (n == 9) us9 = us[0];
    std::printf("%-8d %16.2f %16.2f %18.2f\n", n, us[0], us[1], us[0] / n);
    std::fflush(stdout);  // progress when piped
  }
  std::printf("a 50 Hz control loop has 20000 us per cycle\n");
  std::printf("RESULT {\"cycle_us_9_drives\": %.2f}\n", us9);
  return 0;
}
