// The Thorvald paper's odometry experiment (§3.3.2) in MuJoCo with the IMU fused: the Figure 7 6WD6WS robot drives
// the 77 s loop of commands (base_driver's joint simulator moves its joints, contact physics moves the body, as in
// thorvald_sim's odometry_demo), and odom_fusion's filter (PlanarEkf with odom_fusion's default process noise)
// fuses base_driver's least-squares wheel twist with a flat-mounted gyro: MuJoCo's body yaw rate with white noise
// (thorvald_sim's IMU default, 0.002 rad/s, no bias). Prints the end-point error of wheel-only and fused odometry as
// a share of the distance driven (truth), over --seeds gyro noise streams.
//
//   rosrun thorvald_sim fused_odometry_bench [--seeds 5] [--gyro-noise 0.002] [--gyro-bias 0]
#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>
#include <thorvald_base/testing/odometry_trial.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "thorvald_navigation/planar_ekf.h"
#include "thorvald_sim/drive_loop.h"
#include "thorvald_sim/testing/reference_urdf.h"
#include "thorvald_sim/world.h"

namespace {

using thorvald_navigation::kVx;
using thorvald_navigation::kVy;
using thorvald_navigation::kVyaw;
using thorvald_navigation::State6;

struct Trial {
  double distance_m = 0, wheel_err_m = 0, fused_err_m = 0;
};

Trial runLoop(unsigned seed, double gyro_noise, double gyro_bias) {
  using namespace thorvald_sim;
  const thorvald_base::RobotConfig robot = thorvald_base::figure7Robot();
  RobotSpawn spawn;
  spawn.z = 0.01;
  spawn.mjcf = urdfToMjcf(referenceUrdf(robot, ""), &spawn.root_link);
  Simulation sim(composeScene(makeFlatWorld(), {spawn}, SceneOptions()), {spawn});
  thorvald_base::BaseDriverOptions options;
  options.calculator.estimator = "least_squares";
  DrivenRobot driven(sim, robot, "", options);

  thorvald_navigation::PlanarEkf ekf;
  State6 q;
  q << 0.05, 0.05, 0.06, 0.025, 0.025, 0.02;  // odom_fusion's default process noise
  ekf.setProcessNoise(q);
  ekf.setInitialCovariance(State6::Constant(1e-9));
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, gyro_noise);
  const double min_variance = 1e-6;

  const double dt = 0.02;
  const int steps = static_cast<int>(std::lround(dt / sim.timestep()));
  double t = 0.0;
  auto cycle = [&](const thorvald_base::Twist2D& cmd, bool fuse) {
    driven.command(cmd, t);
    driven.control(t);
    sim.step(steps);
    t += dt;
    if (!fuse) return;
    ekf.predict(t);
    const auto& v = driven.driver().velocity();
    if (v.valid) {
      State6 z = State6::Zero(), var = State6::Constant(1.0);
      z(kVx) = v.twist.vx;
      z(kVy) = v.twist.vy;
      z(kVyaw) = v.twist.wz;
      var(kVx) = std::max(min_variance, v.covariance(0, 0));
      var(kVy) = std::max(min_variance, v.covariance(1, 1));
      var(kVyaw) = std::max(min_variance, v.covariance(2, 2));
      ekf.update(z, var, {false, false, false, true, true, true});
    }
    State6 g = State6::Zero(), gvar = State6::Constant(1.0);
    g(kVyaw) = sim.robotState(0).angular_body.z() + gyro_bias + noise(rng);
    gvar(kVyaw) = std::max(min_variance, gyro_noise * gyro_noise);
    ekf.update(g, gvar, {false, false, false, false, false, true});
  };
  for (int i = 0; i < 50; ++i) cycle({}, false);  // settle on the wheels
  driven.driver().resetOdometry();
  ekf.reset({0.0, 0.0, 0.0}, t);
  const BodyState start = sim.robotState(0);
  const double c0 = std::cos(start.yaw()), s0 = std::sin(start.yaw());
  Trial out;
  Eigen::Vector3d last = start.position;
  auto plan = thorvald_base::paperLoop();
  plan.push_back({3.0, {}});
  double seg_end = t;
  for (const auto& seg : plan) {
    seg_end += seg.duration_s;
    while (t < seg_end - 1e-9) {
      cycle(seg.twist, true);
      const BodyState b = sim.robotState(0);
      out.distance_m += (b.position - last).head<2>().norm();
      last = b.position;
    }
  }
  const BodyState end = sim.robotState(0);
  const double wx = end.position.x() - start.position.x(), wy = end.position.y() - start.position.y();
  const double tx = c0 * wx + s0 * wy, ty = -s0 * wx + c0 * wy;
  const auto& wheel = driven.driver().odometry().pose();
  out.wheel_err_m = std::hypot(wheel.x - tx, wheel.y - ty);
  out.fused_err_m = std::hypot(ekf.state()(thorvald_navigation::kX) - tx, ekf.state()(thorvald_navigation::kY) - ty);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 5;
  double gyro_noise = 0.002, gyro_bias = 0.0;
  CLI::App app{"Figure 7 robot's 77 s loop in MuJoCo: wheel-only vs IMU-fused odometry (odom_fusion's filter)"};
  app.add_option("--seeds", seeds, "gyro noise streams")->check(CLI::Range(1, 100));
  app.add_option("--gyro-noise", gyro_noise, "gyro white noise [rad/s]")->check(CLI::Range(0.0, 1.0));
  app.add_option("--gyro-bias", gyro_bias, "constant gyro bias [rad/s]")->check(CLI::Range(-1.0, 1.0));
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::printf("Figure 7 robot (6WD6WS), 77 s loop + 3 s stop in MuJoCo, gyro noise %.4f rad/s, bias %.4f rad/s\n",
              gyro_noise, gyro_bias);
  std::printf("%6s %14s %18s %18s\n", "seed", "distance [m]", "wheel-only [%]", "fused [%]");
  std::vector<double> wheel, fused;
  try {
    for (int s = 1; s <= seeds; ++s) {
      const Trial r = runLoop(static_cast<unsigned>(s), gyro_noise, gyro_bias);
      wheel.push_back(100.0 * r.wheel_err_m / r.distance_m);
      fused.push_back(100.0 * r.fused_err_m / r.distance_m);
      std::printf("%6d %14.2f %18.3f %18.3f\n", s, r.distance_m, wheel.back(), fused.back());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fused_odometry_bench: %s\n", e.what());
    return 1;
  }
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s / v.size();
  };
  const double worst = *std::max_element(fused.begin(), fused.end());
  std::printf("mean: wheel-only %.3f %%, fused %.3f %% (worst %.3f %%)\n", mean(wheel), mean(fused), worst);
  std::printf(
      "RESULT {\"world\": \"mujoco_flat\", \"robot\": \"figure7_6wd6ws\", \"wheel_odom_err_pct\": %.3f, "
      "\"fused_odom_err_pct\": %.3f, \"fused_odom_err_pct_worst\": %.3f, \"seeds\": %d, \"gyro_noise_radps\": %g}\n",
      mean(wheel), mean(fused), worst, seeds, gyro_noise);
  return 0;
}
