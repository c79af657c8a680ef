#pragma once

#include <thorvald_base/testing/odometry_trial.h>

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "thorvald_sim/drive_loop.h"
#include "thorvald_sim/testing/reference_urdf.h"
#include "thorvald_sim/scene.h"
#include "thorvald_sim/sensors.h"
#include "thorvald_sim/simulation.h"
#include "thorvald_sim/world.h"

namespace thorvald_sim {
namespace test {

/// A four-wheel-steered robot like the paper's standard Thorvald (drives at +-0.675, +-0.6).
inline thorvald_base::RobotConfig fourWheelSteered() {
  thorvald_base::RobotConfig r = thorvald_base::figure7Robot();
  r.source = "4ws test robot";
  r.drives.resize(4);
  const double xy[4][2] = {{-0.675, -0.6}, {0.675, -0.6}, {0.675, 0.6}, {-0.675, 0.6}};
  for (int i = 0; i < 4; ++i) r.drives[i].x = xy[i][0], r.drives[i].y = xy[i][1];
  return r;
}

/// A two-wheel differential robot with two passive wheels at the rear.
inline thorvald_base::RobotConfig differential() {
  thorvald_base::RobotConfig r = fourWheelSteered();
  r.source = "2wd test robot";
  r.base_calculator = "pltf_clc_2wdiff::PltfClc2WDiff";
  r.drives.resize(2);
  r.drives[0].x = r.drives[1].x = 0.0;
  r.drives[0].y = -0.6;
  r.drives[1].y = 0.6;
  for (auto& d : r.drives) d.type = 1;
  thorvald_base::PassiveWheelConfig c;
  c.r_wheel = 0.1;
  c.w_wheel = 0.05;
  c.x = -0.8;
  c.offset = 0.05;
  c.y = -0.4;
  r.casters.push_back(c);
  c.y = 0.4;
  r.casters.push_back(c);
  return r;
}

/// One world, robots spawned along y, each with an in-process base_driver.
struct TestScene {
  std::unique_ptr<Simulation> sim;
  std::vector<std::unique_ptr<DrivenRobot>> robots;
  double t = 0.0;

  TestScene(const WorldDescription& world, const std::vector<thorvald_base::RobotConfig>& configs,
            const std::vector<std::array<double, 3>>& poses = {}, const SceneOptions& options = SceneOptions()) {
    std::vector<RobotSpawn> spawns;
    for (size_t i = 0; i < configs.size(); ++i) {
      RobotSpawn s;
      s.name = configs.size() > 1 ? "robot" + std::to_string(i) : "";
      s.mjcf = urdfToMjcf(referenceUrdf(configs[i], s.name), &s.root_link);
      if (i < poses.size())
        s.x = poses[i][0], s.y = poses[i][1], s.yaw = poses[i][2];
      else
        s.y = 4.0 * i;
      s.z = 0.01;
      spawns.push_back(s);
    }
    sim = std::make_unique<Simulation>(composeScene(world, spawns, options), spawns);
    for (size_t i = 0; i < configs.size(); ++i)
      robots.push_back(std::make_unique<DrivenRobot>(*sim, configs[i], spawns[i].name));
  }

  /// Runs `seconds` with control at 50 Hz; commands stay as set.
  void run(double seconds) {
    const int steps_per_cycle = static_cast<int>(std::lround(0.02 / sim->timestep()));
    const double end = t + seconds - 1e-9;
    while (t < end) {
      for (auto& r : robots) r->control(t);
      sim->step(steps_per_cycle);
      t += 0.02;
    }
  }
  void command(size_t i, double vx, double vy, double wz) { robots[i]->command({vx, vy, wz}, t); }
  /// Keeps commanding (the driver times out after 0.5 s without commands).
  void drive(size_t i, double vx, double vy, double wz, double seconds) {
    const double end = t + seconds - 1e-9;
    while (t < end) {
      command(i, vx, vy, wz);
      run(0.1);
    }
  }
};

/// A world without robots, compiled and with its positions computed (mj_forward), for sensors against known
/// geometry.
struct StaticWorld {
  ModelPtr model;
  DataPtr data;
  explicit StaticWorld(const WorldDescription& w) {
    model = compileXml(composeScene(w, {}, SceneOptions()), "test world");
    data.reset(mj_makeData(model.get()));
    mj_forward(model.get(), data.get());
  }
};

/// Optical frame (z forward, y down) at `origin` looking along `forward`, with `down` as near its y as it can be.
inline SensorPose optical(const Eigen::Vector3d& origin, const Eigen::Vector3d& forward, const Eigen::Vector3d& down) {
  SensorPose p;
  p.origin = origin;
  p.rotation.col(2) = forward.normalized();
  p.rotation.col(1) = (down - down.dot(p.rotation.col(2)) * p.rotation.col(2)).normalized();
  p.rotation.col(0) = p.rotation.col(1).cross(p.rotation.col(2));
  return p;
}

/// Sensor frame (x forward, z up) at `origin` looking along the horizontal `forward`.
inline SensorPose lookingAlong(const Eigen::Vector3d& origin, const Eigen::Vector3d& forward) {
  SensorPose p;
  p.origin = origin;
  p.rotation.col(0) = forward.normalized();
  p.rotation.col(2) = Eigen::Vector3d::UnitZ();
  p.rotation.col(1) = p.rotation.col(2).cross(p.rotation.col(0));
  return p;
}

}  // namespace test
}  // namespace thorvald_sim
