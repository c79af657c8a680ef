// The Thorvald paper's odometry experiment (§3.3.2) in MuJoCo: the Figure 7 asymmetric 6WD6WS robot drives the
// 77 s loop of commands. Prints the distance travelled by ground truth and by each odometry estimator (least
// squares, the paper's random pairs), the end-point errors and each estimator's velocity errors, writes the paths
// and velocities as CSV and plots the paper's Figure 8 (paths) and Figure 9 (commanded and estimated vx, vy, wz over
// time) to PNGs.
//
// `--realism ideal` (default): base_driver's joint simulator moves the joints, contact physics moves the body, on
// flat dry concrete (the figures as before). `--realism datasheet`: the drives' encoders read MuJoCo's joints
// (PhysicsDrive), so wheel slip and the body's motion over bumps reach the odometry; the ground is the paper's
// (tarmac: dry concrete) with gravel-sized bumps unless --ground / --bumps say otherwise.
//
//   rosrun thorvald_sim odometry_demo [--realism ideal|datasheet] [--ground dry_concrete|wet_concrete|loose_soil]
//     [--bumps M] [--suspension RAD] [--urdf FILE] [--csv FILE] [--png FILE] [--png-velocities FILE]
// Without --urdf it uses reference_urdf.h's model of the robot; with the robot's own model:
//   rosrun thorvald_sim odometry_demo --urdf <(rosrun thorvald_model urdf_generator --config
//     $(rospack find thorvald_bringup)/config/figure7_6wd6ws_asymmetric.yaml --tf-prefix '' --robot-name figure7)
// (one command line)
#include <CLI/CLI.hpp>
#include <thorvald_base/standard_calculator.h>
#include <thorvald_base/testing/odometry_trial.h>
#include <thorvald_common/command_line.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
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

struct DemoOptions {
  std::string urdf_file, csv = "odometry_demo.csv", png = "odometry_demo.png",
                         png_velocities = "odometry_demo_velocities.png";
  Realism realism = Realism::kIdeal;
  Ground ground = Ground::kDryConcrete;
  double bumps_m = 0.0, suspension_rad = 0.0;
};

/// Sums of squared velocity errors against ground truth, per estimator.
struct VelocityErrors {
  double vx = 0, vy = 0, wz = 0;
  int n = 0;
  void add(const thorvald_base::Twist2D& est, const BodyState& truth) {
    vx += std::pow(est.vx - truth.linear_body.x(), 2);
    vy += std::pow(est.vy - truth.linear_body.y(), 2);
    wz += std::pow(est.wz - truth.angular_body.z(), 2);
    ++n;
  }
  double rms(double sum) const { return n > 0 ? std::sqrt(sum / n) : 0.0; }
};

void runPlot(const std::string& script, const std::string& csv, const std::string& png, const std::string& title) {
  const std::string plot = selfDir() + "/" + script;
  if (png.empty() || access(plot.c_str(), X_OK) != 0) return;
  const std::string cmd = "/usr/bin/python3 '" + plot + "' '" + csv + "' '" + png + "' '" + title + "'";
  if (std::system(cmd.c_str()) == 0)
    std::printf("plot: %s\n", png.c_str());
  else
    std::printf("plot: failed (%s)\n", cmd.c_str());
}

/// The CSV's velocity columns: commanded, true, least squares, random pairs (vx, vy, wz each), ending the row.
void writeTwists(std::ostream& out, const thorvald_base::Twist2D& cmd, const thorvald_base::Twist2D& truth,
                 const thorvald_base::Twist2D& ls, const thorvald_base::Twist2D& paper) {
  for (const auto* v : {&cmd, &truth, &ls, &paper}) out << "," << v->vx << "," << v->vy << "," << v->wz;
  out << "\n";
}

/// The flat world (with bumps if asked) on the ground asked, the robot spawned with its suspension if asked.
std::unique_ptr<Simulation> makeSimulation(const DemoOptions& opt, const thorvald_base::RobotConfig& robot) {
  RobotSpawn spawn;
  spawn.z = 0.01;
  const std::string urdf = opt.urdf_file.empty() ? referenceUrdf(robot, "") : readFile(opt.urdf_file);
  if (urdf.empty()) throw std::runtime_error("cannot read " + opt.urdf_file);
  spawn.mjcf = urdfToMjcf(urdf, &spawn.root_link);
  if (opt.suspension_rad > 0.0) spawn.suspension_rad.assign(robot.drives.size(), opt.suspension_rad);
  WorldDescription world = makeFlatWorld();
  if (opt.bumps_m > 0.0) {
    BumpOptions bumps;
    bumps.amplitude_m = opt.bumps_m;
    world = withBumps(world, bumps);
  }
  SceneOptions scene;
  scene.ground = opt.ground;
  return std::make_unique<Simulation>(composeScene(world, {spawn}, scene), std::vector<RobotSpawn>{spawn});
}

/// What a run measured.
struct DemoResult {
  double duration_s = 0, truth_dist = 0, ls_dist = 0, paper_dist = 0, err_ls = 0, err_paper = 0, truth_end = 0;
  VelocityErrors v_ls, v_paper;
};

void report(const DemoOptions& opt, const DemoResult& r) {
  const auto& ls = r.v_ls;
  const auto& rp = r.v_paper;
  std::printf("Figure 7 robot (6WD6WS), %.0f s loop of commands + 3 s to stop, in MuJoCo (%s: %s%s%s)\n",
              r.duration_s - 3.0, realismName(opt.realism), groundName(opt.ground),
              opt.bumps_m > 0 ? (", bumps " + std::to_string(opt.bumps_m) + " m").c_str() : ", flat",
              opt.suspension_rad > 0 ? ", suspension" : "");
  std::printf("%-28s %12s %18s %14s %10s %10s %10s\n", "path", "distance [m]", "end error [m]", "error [%]", "vx rms",
              "vy rms", "wz rms");
  std::printf("%-28s %12.2f %18s %14s\n", "ground truth (MuJoCo)", r.truth_dist, "-", "-");
  std::printf("%-28s %12.2f %18.3f %14.2f %10.4f %10.4f %10.4f\n", "least squares (default)", r.ls_dist, r.err_ls,
              100 * r.err_ls / r.truth_dist, ls.rms(ls.vx), ls.rms(ls.vy), ls.rms(ls.wz));
  std::printf("%-28s %12.2f %18.3f %14.2f %10.4f %10.4f %10.4f\n", "random pairs (paper)", r.paper_dist, r.err_paper,
              100 * r.err_paper / r.truth_dist, rp.rms(rp.vx), rp.rms(rp.vy), rp.rms(rp.wz));
  std::printf("truth ends %.3f m from its start (the commands would close the loop exactly)\n", r.truth_end);
  std::printf("model: %s\n",
              opt.urdf_file.empty() ? "thorvald_sim's reference URDF of the robot" : opt.urdf_file.c_str());
  std::printf("paths and velocities: %s\n", opt.csv.c_str());
  std::printf(
      "RESULT {\"distance_truth_m\": %.3f, \"distance_ls_m\": %.3f, \"distance_paper_m\": %.3f, "
      "\"end_error_ls_m\": %.4f, \"end_error_paper_m\": %.4f, \"realism\": \"%s\", \"ground\": \"%s\", "
      "\"bumps_m\": %.3f, \"suspension_rad\": %.3f, \"vx_rms_ls_mps\": %.4f, \"vy_rms_ls_mps\": %.4f, "
      "\"wz_rms_ls_radps\": %.4f, \"vx_rms_paper_mps\": %.4f, \"vy_rms_paper_mps\": %.4f, "
      "\"wz_rms_paper_radps\": %.4f}\n",
      r.truth_dist, r.ls_dist, r.paper_dist, r.err_ls, r.err_paper, realismName(opt.realism), groundName(opt.ground),
      opt.bumps_m, opt.suspension_rad, ls.rms(ls.vx), ls.rms(ls.vy), ls.rms(ls.wz), rp.rms(rp.vx), rp.rms(rp.vy),
      rp.rms(rp.wz));
  const std::string title = std::string("Figure 7 robot, 77 s loop in MuJoCo (") + realismName(opt.realism) + ", " +
                            groundName(opt.ground) + (opt.bumps_m > 0 ? ", bumps" : "") + ")";
  runPlot("plot_demo_paths.py", opt.csv, opt.png, title);
  runPlot("plot_demo_velocities.py", opt.csv, opt.png_velocities, title);
}

int runDemo(const DemoOptions& opt) {
  const thorvald_base::RobotConfig robot = thorvald_base::figure7Robot();
  const auto simulation = makeSimulation(opt, robot);
  Simulation& sim = *simulation;
  thorvald_base::BaseDriverOptions options;
  options.calculator.estimator = "least_squares";
  const bool datasheet = opt.realism == Realism::kDatasheet;
  DrivenRobot driven(sim, robot, "", options, datasheet ? EncoderSource::kPhysics : EncoderSource::kJointSimulator);
  // Both estimators read the same joint states, each through its own model (the driver's is least squares).
  thorvald_base::StandardCalculator paper, ls;
  thorvald_base::CalculatorOptions paper_options, ls_options;
  paper_options.estimator = "random_pairs";
  ls_options.estimator = "least_squares";
  paper.configure(robot.drives, robot.passive_wheels, paper_options);
  ls.configure(robot.drives, robot.passive_wheels, ls_options);
  thorvald_base::OdometryIntegrator paper_odom;

  const double dt = 0.02;
  const int steps = static_cast<int>(std::lround(dt / sim.timestep()));
  double t = 0.0;
  thorvald_base::Twist2D ls_twist, paper_twist;
  auto cycle = [&](const thorvald_base::Twist2D& cmd) {
    driven.command(cmd, t);
    driven.control(t);
    const auto p = paper.estimateTwist(driven.driver().feedback());
    paper_twist = p.twist;
    ls_twist = ls.estimateTwist(driven.driver().feedback()).twist;
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
  std::ofstream out(opt.csv);
  out << "t,truth_x,truth_y,ls_x,ls_y,paper_x,paper_y,cmd_vx,cmd_vy,cmd_wz,truth_vx,truth_vy,truth_wz,ls_vx,ls_vy,"
         "ls_wz,paper_vx,paper_vy,paper_wz\n";
  auto plan = thorvald_base::paperLoop();
  plan.push_back({3.0, {}});
  double seg_end = t, t0 = t;
  int k = 0;
  VelocityErrors err_v_ls, err_v_paper;
  for (const auto& seg : plan) {
    seg_end += seg.duration_s;
    while (t < seg_end - 1e-9) {
      cycle(seg.twist);
      const BodyState b = sim.robotState(0);
      truth_dist += (b.position - last).head<2>().norm();
      last = b.position;
      err_v_ls.add(ls_twist, b);
      err_v_paper.add(paper_twist, b);
      if (++k % 5 == 0) {
        const double wx = b.position.x() - start.position.x(), wy = b.position.y() - start.position.y();
        const auto& lp = driven.driver().odometry().pose();
        const auto& pp = paper_odom.pose();
        out << t - t0 << "," << c0 * wx + s0 * wy << "," << -s0 * wx + c0 * wy << "," << lp.x << "," << lp.y << ","
            << pp.x << "," << pp.y;
        writeTwists(out, seg.twist, {b.linear_body.x(), b.linear_body.y(), b.angular_body.z()}, ls_twist, paper_twist);
      }
    }
  }
  out.close();
  const BodyState end = sim.robotState(0);
  const double wx = end.position.x() - start.position.x(), wy = end.position.y() - start.position.y();
  const double tx = c0 * wx + s0 * wy, ty = -s0 * wx + c0 * wy;
  const auto& lso = driven.driver().odometry();
  DemoResult r;
  r.duration_s = t - t0, r.truth_dist = truth_dist;
  r.ls_dist = lso.distance(), r.paper_dist = paper_odom.distance();
  r.err_ls = std::hypot(lso.pose().x - tx, lso.pose().y - ty);
  r.err_paper = std::hypot(paper_odom.pose().x - tx, paper_odom.pose().y - ty);
  r.truth_end = std::hypot(tx, ty);
  r.v_ls = err_v_ls, r.v_paper = err_v_paper;
  report(opt, r);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  DemoOptions opt;
  std::string realism = "ideal", ground;
  double bumps = -1.0;
  CLI::App app{"The Thorvald paper's odometry experiment (Figure 7 robot, 77 s loop) in MuJoCo"};
  app.add_option("--urdf", opt.urdf_file, "URDF of the robot (default: the reference model)")->check(CLI::ExistingFile);
  app.add_option("--realism", realism,
                 "ideal (joint simulator, flat dry concrete) | datasheet (encoders from the "
                 "physics, bumps)")
      ->check(CLI::IsMember({"ideal", "datasheet"}));
  app.add_option("--ground", ground, "dry_concrete | wet_concrete | loose_soil (default dry_concrete)")
      ->check(CLI::IsMember({"dry_concrete", "wet_concrete", "loose_soil"}));
  app.add_option("--bumps", bumps, "bump height on the ground [m] (default 0; datasheet 0.03)")
      ->check(CLI::Range(0.0, 0.3));
  app.add_option("--suspension", opt.suspension_rad, "suspension travel of every drive [rad] (default 0: rigid)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--csv", opt.csv, "where the paths and velocities are written");
  app.add_option("--png", opt.png, "where the plot of the paths (Figure 8) is written");
  app.add_option("--png-velocities", opt.png_velocities,
                 "where the plot of the velocities over time (Figure 9) is written");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  opt.realism = *realismFromName(realism);
  if (!ground.empty()) opt.ground = *groundFromName(ground);
  opt.bumps_m = bumps >= 0.0 ? bumps : (opt.realism == Realism::kDatasheet ? 0.03 : 0.0);
  try {
    return runDemo(opt);
  } catch (const std::exception& e) {
    std::cerr << "odometry_demo: " << e.what() << "\n";
    return 1;
  }
}
