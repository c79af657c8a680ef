#pragma once

// The parts rtf_bench's scenes share (rtf_bench.cpp: flat scenes and the greenhouse robot; cotton_camera_rtf.cpp:
// the cotton camera): a scene with driven robots, the clocks, the drive loop, sensor mounts and rate timers.

#include <chrono>
#include <cmath>
#include <ctime>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <thorvald_base/testing/odometry_trial.h>

#include "thorvald_sim/drive_loop.h"
#include "thorvald_sim/sensors.h"
#include "thorvald_sim/testing/reference_urdf.h"
#include "thorvald_sim/world.h"

namespace rtf_bench {

inline thorvald_base::RobotConfig fourWheelSteered() {
  thorvald_base::RobotConfig r = thorvald_base::figure7Robot();
  r.drives.resize(4);
  const double xy[4][2] = {{-0.675, -0.6}, {0.675, -0.6}, {0.675, 0.6}, {-0.675, 0.6}};
  for (int i = 0; i < 4; ++i) r.drives[i].x = xy[i][0], r.drives[i].y = xy[i][1];
  return r;
}

struct Run {
  std::unique_ptr<thorvald_sim::Simulation> sim;
  std::vector<std::unique_ptr<thorvald_sim::DrivenRobot>> robots;
};

inline Run build(const thorvald_sim::WorldDescription& world, int n, const thorvald_base::RobotConfig& robot, double x,
                 double y, const thorvald_sim::SceneOptions& options = thorvald_sim::SceneOptions()) {
  using namespace thorvald_sim;
  Run run;
  std::vector<RobotSpawn> spawns;
  for (int i = 0; i < n; ++i) {
    RobotSpawn s;
    s.name = "robot" + std::to_string(i);
    s.mjcf = urdfToMjcf(referenceUrdf(robot, s.name), &s.root_link);
    s.x = x;
    s.y = y + 5.0 * i;
    s.z = 0.01;
    spawns.push_back(s);
  }
  run.sim = std::make_unique<Simulation>(composeScene(world, spawns, options), spawns);
  for (int i = 0; i < n; ++i) run.robots.push_back(std::make_unique<DrivenRobot>(*run.sim, robot, spawns[i].name));
  return run;
}

// The machine is shared: besides wall time, the CPU time this process got (all its threads) tells what one free
// core would do.
inline double wallNow() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
inline double cpuNow() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// Simulated seconds per wall second and per CPU second.
struct Rate {
  double wall = 0, cpu = 0;
};

// Drives every robot with `cmd` for `seconds` of simulated time at 50 Hz control; `sensors` runs each cycle.
inline Rate drive(Run& run, double seconds, const thorvald_base::Twist2D& cmd,
                  const std::function<void(double)>& sensors) {
  const int steps = static_cast<int>(std::lround(0.02 / run.sim->timestep()));
  const double t0 = run.sim->time(), w0 = wallNow(), c0 = cpuNow();
  while (run.sim->time() - t0 < seconds) {
    const double t = run.sim->time();
    for (auto& r : run.robots) {
      r->command(cmd, t);
      r->control(t);
    }
    run.sim->step(steps);
    sensors(run.sim->time());
  }
  return {(run.sim->time() - t0) / (wallNow() - w0), (run.sim->time() - t0) / (cpuNow() - c0)};
}

// A sensor mounted on robot 0's base_link.
inline thorvald_sim::SensorPose mount(const Run& run, const Eigen::Vector3d& xyz, const Eigen::Matrix3d& r) {
  const thorvald_sim::BodyState b = run.sim->robotState(0);
  thorvald_sim::SensorPose p;
  p.origin = b.position + b.orientation * xyz;
  p.rotation = b.orientation.toRotationMatrix() * r;
  return p;
}

// Optical frame (z forward, x right, y down) of a camera pitched `pitch` down from looking forward.
inline Eigen::Matrix3d opticalPitched(double pitch) {
  return Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix() *
         (Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0).finished();
}

// Calls `f` at `rate_hz` in simulated time.
struct Every {
  double period, next = 0.0;
  explicit Every(double rate_hz) : period(1.0 / rate_hz) {}
  bool due(double t) {
    if (t + 1e-9 < next) return false;
    next = std::max(next + period, t);
    return true;
  }
};

// Adds the CPU time `f` takes to `*acc` [s].
inline void timed(double* acc, const std::function<void()>& f) {
  const double c0 = cpuNow();
  f();
  *acc += cpuNow() - c0;
}

}  // namespace rtf_bench
