// The Thorvald paper's odometry experiment (§3.3.2) in MuJoCo: the Figure 7 asymmetric 6WD6WS robot drives the
// 77 s loop of commands; base_driver's joint simulator moves its joints, contact physics moves the body. Prints the
// distance travelled by ground truth and by each odometry estimator (least squares, the paper's random pairs),
// the end-point errors, writes the three paths as CSV and plots them to a PNG.
//
//   rosrun thorvald_sim odometry_demo [--urdf FILE] [--csv FILE] [--png FILE]
// Without --urdf it uses reference_urdf.h's model of the robot; with the robot's own model:
//   rosrun thorvald_sim odometry_demo --urdf <(rosrun thorvald_model urdf_generator --config
//     $(rospack find thorvald_bringup)/config/figure7_6wd6ws_asymmetric.yaml --tf-prefix '' --robot-name figure7)
// (one command line)
#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>
#include <thorvald_base/testing/odometry_trial.h>
#include <thorvald_base/standard_calculator.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "thorvald_sim/drive_loop.h"
#include "thorvald_sim/testing/reference_urdf.h"
#include "thorvald_sim/world.h"

using namespace thorvald_sim;

namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string selfDir() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof(buf) - 1);
  if (n <= 0) return ".";
  std::string p(buf, n);
  return p.substr(0, p.rfind('/'));
}

}  // namespace

int main(int argc, char** argv) {
  std::string urdf_file, csv = "odometry_demo.csv", png = "odometry_demo.png";
  CLI::App app{"The Thorvald paper's odometry experiment (Figure 7 robot, 77 s loop) in MuJoCo"};
  app.add_option("--urdf", urdf_file, "URDF of the robot (default: the reference model)")->check(CLI::ExistingFile);
  app.add_option("--csv", csv, "where the three paths are written");
  app.add_option("--png", png, "where the plot of the paths is written");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const thorvald_base::RobotConfig robot = thorvald_base::figure7Robot();
  try {
    RobotSpawn spawn;
    spawn.z = 0.01;
    const std::string urdf = urdf_file.empty() ? referenceUrdf(robot, "") : readFile(urdf_file);
    if (urdf.empty()) throw std::runtime_error("cannot read " + urdf_file);
    spawn.mjcf = urdfToMjcf(urdf, &spawn.root_link);
    Simulation sim(composeScene(makeFlatWorld(), {spawn}, SceneOptions()), {spawn});
    thorvald_base::BaseDriverOptions options;
    options.calculator.estimator = "least_squares";
    DrivenRobot driven(sim, robot, "", options);
    // The paper's estimator reads the same joint states through its own model.
    thorvald_base::StandardCalculator paper;
    thorvald_base::CalculatorOptions paper_options;
    paper_options.estimator = "random_pairs";
    paper.configure(robot.drives, robot.passive_wheels, paper_options);
    thorvald_base::OdometryIntegrator paper_odom;

    const double dt = 0.02;
    const int steps = static_cast<int>(std::lround(dt / sim.timestep()));
    double t = 0.0;
    auto cycle = [&](const thorvald_base::Twist2D& cmd) {
      driven.command(cmd, t);
      driven.control(t);
      const auto p = paper.estimateTwist(driven.driver().feedback());
      if (t > 0) paper_odom.integrate(p.twist, p.covariance, dt);
      sim.step(steps);
      t += dt;
    };
    for (int i = 0; i < 50; ++i) cycle({});  // settle on the wheels
    driven.driver().resetOdometry();
    paper_odom.reset();
    const BodyState start = sim.robotState(0);
    const double c0 = std::cos(start.yaw()), s0 = std::sin(start.yaw());
    double truth_dist = 0.0;
    Eigen::Vector3d last = start.position;
    std::ofstream out(csv);
    out << "t,truth_x,truth_y,ls_x,ls_y,paper_x,paper_y\n";
    auto plan = thorvald_base::paperLoop();
    plan.push_back({3.0, {}});
    double seg_end = t, t0 = t;
    int k = 0;
    for (const auto& seg : plan) {
      seg_end += seg.duration_s;
      while (t < seg_end - 1e-9) {
        cycle(seg.twist);
        const BodyState b = sim.robotState(0);
        truth_dist += (b.position - last).head<2>().norm();
        last = b.position;
        if (++k % 5 == 0) {
          const double wx = b.position.x() - start.position.x(), wy = b.position.y() - start.position.y();
          const auto& ls = driven.driver().odometry().pose();
          const auto& pp = paper_odom.pose();
          out << t - t0 << "," << c0 * wx + s0 * wy << "," << -s0 * wx + c0 * wy << "," << ls.x << "," << ls.y << ","
              << pp.x << "," << pp.y << "\n";
        }
      }
    }
    out.close();
    const BodyState end = sim.robotState(0);
    const double wx = end.position.x() - start.position.x(), wy = end.position.y() - start.position.y();
    const double tx = c0 * wx + s0 * wy, ty = -s0 * wx + c0 * wy;
    const auto& ls = driven.driver().odometry();
    const double err_ls = std::hypot(ls.pose().x - tx, ls.pose().y - ty);
    const double err_paper = std::hypot(paper_odom.pose().x - tx, paper_odom.pose().y - ty);
    std::printf("Figure 7 robot (6WD6WS), %.0f s loop of commands + 3 s to stop, in MuJoCo (flat ground)\n",
                t - t0 - 3.0);
    std::printf("%-28s %12s %18s %14s\n", "path", "distance [m]", "end error [m]", "error [%]");
    std::printf("%-28s %12.2f %18s %14s\n", "ground truth (MuJoCo)", truth_dist, "-", "-");
    std::printf("%-28s %12.2f %18.3f %14.2f\n", "least squares (default)", ls.distance(), err_ls,
                100 * err_ls / truth_dist);
    std::printf("%-28s %12.2f %18.3f %14.2f\n", "random pairs (paper)", paper_odom.distance(), err_paper,
                100 * err_paper / truth_dist);
    std::printf("truth ends %.3f m from its start (the commands would close the loop exactly)\n", std::hypot(tx, ty));
    std::printf("model: %s\n", urdf_file.empty() ? "thorvald_sim's reference URDF of the robot" : urdf_file.c_str());
    std::printf("paths: %s\n", csv.c_str());
    std::printf(
        "RESULT {\"distance_truth_m\": %.3f, \"distance_ls_m\": %.3f, \"distance_paper_m\": %.3f, "
        "\"end_error_ls_m\": %.4f, \"end_error_paper_m\": %.4f}\n",
        truth_dist, ls.distance(), paper_odom.distance(), err_ls, err_paper);
    const std::string plot = selfDir() + "/plot_demo_paths.py";
    if (!png.empty() && access(plot.c_str(), X_OK) == 0) {
      const std::string cmd = "/usr/bin/python3 '" + plot + "' '" + csv + "' '" + png + "'";
      if (std::system(cmd.c_str()) == 0)
        std::printf("plot: %s\n", png.c_str());
      else
        std::printf("plot: failed (%s)\n", cmd.c_str());
    }
  } catch (const std::exception& e) {
    std::cerr << "odometry_demo: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
