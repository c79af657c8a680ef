// Real-time factor (simulated seconds per wall second) of the MuJoCo simulation with in-process base_drivers:
// 1, 2, 4, 8 four-wheel-steered robots driving circles on flat ground; one greenhouse robot with a lidar
// (40 Hz, 1081 beams), four ultrasonics (20 Hz) and a 30 Hz 640x480 depth camera.
//
//   rosrun thorvald_sim rtf_bench [--seconds S]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include <thorvald_base/odometry_trial.h>

#include "thorvald_sim/drive_loop.h"
#include "thorvald_sim/reference_urdf.h"
#include "thorvald_sim/sensors.h"
#include "thorvald_sim/world.h"

using namespace thorvald_sim;

namespace {

thorvald_base::RobotConfig fourWheelSteered() {
  thorvald_base::RobotConfig r = thorvald_base::figure7Robot();
  r.drives.resize(4);
  const double xy[4][2] = {{-0.675, -0.6}, {0.675, -0.6}, {0.675, 0.6}, {-0.675, 0.6}};
  for (int i = 0; i < 4; ++i) r.drives[i].x = xy[i][0], r.drives[i].y = xy[i][1];
  return r;
}

struct Run {
  std::unique_ptr<Simulation> sim;
  std::vector<std::unique_ptr<DrivenRobot>> robots;
};

Run build(const WorldDescription& world, int n) {
  Run run;
  std::vector<RobotSpawn> spawns;
  for (int i = 0; i < n; ++i) {
    RobotSpawn s;
    s.name = "robot" + std::to_string(i);
    s.mjcf = urdfToMjcf(referenceUrdf(fourWheelSteered(), s.name), &s.root_link);
    s.x = -3.0;
    s.y = 5.0 * i;
    s.z = 0.01;
    spawns.push_back(s);
  }
  run.sim = std::make_unique<Simulation>(composeScene(world, spawns, SceneOptions()), spawns);
  for (int i = 0; i < n; ++i)
    run.robots.push_back(std::make_unique<DrivenRobot>(*run.sim, fourWheelSteered(), spawns[i].name));
  return run;
}

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// Drives every robot in circles for `seconds` of simulated time at 50 Hz control; `sensors` runs each cycle.
template <typename F>
double drive(Run& run, double seconds, F&& sensors) {
  const int steps = static_cast<int>(std::lround(0.02 / run.sim->timestep()));
  const double t0 = run.sim->time(), w0 = now();
  while (run.sim->time() - t0 < seconds) {
    const double t = run.sim->time();
    for (auto& r : run.robots) {
      r->command({0.8, 0.0, 0.3}, t);
      r->control(t);
    }
    run.sim->step(steps);
    sensors(run.sim->time());
  }
  return (run.sim->time() - t0) / (now() - w0);
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 20.0;
  if (argc == 3 && std::string(argv[1]) == "--seconds") seconds = std::atof(argv[2]);
  std::printf("%-40s %14s\n", "scene", "real-time x");
  double rtf[9] = {0};
  for (int n : {1, 2, 4, 8}) {
    Run run = build(makeFlatWorld(), n);
    rtf[n] = drive(run, seconds, [](double) {});
    std::printf("%-40s %14.1f\n", ("flat, " + std::to_string(n) + " robot(s)").c_str(), rtf[n]);
  }
  // The greenhouse robot and its sensors, each at its own rate.
  Run run = build(makeGreenhouseWorld(GreenhouseParams(), nullptr), 1);
  RayCaster caster(run.sim->model(), run.sim->data(), run.sim->robot(0).root_body);
  LidarSpec lidar;
  lidar.samples = 1081;
  UltrasonicSpec us;
  DepthCameraSpec depth;  // 640 x 480
  std::mt19937 rng(1);
  double next_lidar = 0, next_us = 0, next_cam = 0;
  long beams = 0, frames = 0;
  auto mount = [&](const Eigen::Vector3d& xyz, const Eigen::Matrix3d& r) {
    const BodyState b = run.sim->robotState(0);
    SensorPose p;
    p.origin = b.position + b.orientation * xyz;
    p.rotation = b.orientation.toRotationMatrix() * r;
    return p;
  };
  Eigen::Matrix3d down, optical;
  down << 0, 0, 1, 0, 1, 0, -1, 0, 0;  // x axis pointing down
  // Optical frame pitched 0.5 rad down: z forward-down, x right, y down-back.
  optical = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix() *
            (Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0).finished();
  const double sensor_seconds = std::min(seconds, 3.0);
  const double rtf_sensors = drive(run, sensor_seconds, [&](double t) {
    if (t >= next_lidar) {
      next_lidar += 1.0 / 40;
      beams += static_cast<long>(
          simulateLidar(caster, mount({0.7, 0, 0.7}, Eigen::Matrix3d::Identity()), lidar, rng).size());
    }
    if (t >= next_us) {
      next_us += 1.0 / 20;
      for (double y : {-0.6, -0.2, 0.2, 0.6}) simulateUltrasonic(caster, mount({0.8, y, 0.4}, down), us, rng);
    }
    if (t >= next_cam) {
      next_cam += 1.0 / 30;
      simulateDepth(caster, mount({0.8, 0, 0.8}, optical), depth, rng);
      ++frames;
    }
  });
  std::printf("%-40s %14.2f\n", "greenhouse, lidar + 4 US + 640x480@30Hz", rtf_sensors);
  std::printf("(%.0f s simulated per flat scene, %.0f s with sensors: %ld depth frames, %ld lidar beams)\n", seconds,
              sensor_seconds, frames, beams);
  std::printf(
      "RESULT {\"rtf_1_robot\": %.2f, \"rtf_2_robots\": %.2f, \"rtf_4_robots\": %.2f, \"rtf_8_robots\": %.2f, "
      "\"rtf_greenhouse_sensors\": %.3f}\n",
      rtf[1], rtf[2], rtf[4], rtf[8], rtf_sensors);
  return 0;
}
