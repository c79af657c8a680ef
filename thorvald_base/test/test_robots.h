#pragma once

#include <string>
#include <vector>

#include "thorvald_base/testing/odometry_trial.h"
#include "thorvald_base/robot_config.h"

namespace thorvald_base {
namespace test {

/// A standard Thorvald drive module at (x, y), with an optional steering limit.
inline DriveConfig drive(int index, double x, double y, int type = 0, double str_lim = 3.078027759) {
  DriveConfig d = thorvaldDriveModule(index, x, y, type);
  d.str_lim = str_lim;
  return d;
}

struct TestRobot {
  std::string name;
  std::string calculator;  ///< "standard", "diff" or "one_wheel"
  RobotConfig config;
};

inline PassiveWheelConfig passive(double x, double y) {
  PassiveWheelConfig p;
  p.x = x;
  p.y = y;
  return p;
}

/// The robots of the Thorvald paper's Figure 10 (a-h) and the asymmetric 6WD6WS robot of its Figure 7.
inline std::vector<TestRobot> paperRobots() {
  std::vector<TestRobot> robots;
  auto add = [&](const std::string& name, const std::string& calc, std::vector<DriveConfig> drives,
                 std::vector<PassiveWheelConfig> passive_wheels = {}) {
    TestRobot r{name, calc, {}};
    r.config.drives = drives;
    r.config.passive_wheels = passive_wheels;
    robots.push_back(r);
  };
  add("a_4wd4ws_wide", "standard",
      {drive(0, -0.678, -0.75), drive(1, 0.678, -0.75), drive(2, 0.678, 0.75), drive(3, -0.678, 0.75)});
  add("b_4wd2ws_tall", "standard",
      {drive(0, -0.678, -0.6, 1), drive(1, 0.678, -0.6), drive(2, 0.678, 0.6), drive(3, -0.678, 0.6, 1)});
  add("c_6wd6ws", "standard",
      {drive(0, -1.0, -0.75), drive(1, 0.0, -0.75), drive(2, 1.0, -0.75), drive(3, 1.0, 0.75), drive(4, 0.0, 0.75),
       drive(5, -1.0, 0.75)});
  add("d_1wd1ws_rear", "one_wheel", {drive(0, -0.6, 0.0)}, {passive(0.4, -0.35), passive(0.4, 0.35)});
  add("e_2wd_diff", "diff", {drive(0, 0.0, -0.35, 1), drive(1, 0.0, 0.35, 1)});
  add("f_4wd4ws_slim", "standard",
      {drive(0, -0.678, -0.3), drive(1, 0.678, -0.3), drive(2, 0.678, 0.3), drive(3, -0.678, 0.3)});
  add("g_1wd1ws_front", "one_wheel", {drive(0, 0.6, 0.0)}, {passive(-0.4, -0.35), passive(-0.4, 0.35)});
  std::vector<DriveConfig> nine;
  for (int i = 0; i < 9; ++i) nine.push_back(drive(i, -1.2 + 1.2 * (i / 3), -1.0 + 1.0 * (i % 3)));
  add("h_9wd9ws", "standard", nine);
  add("fig7_6wd6ws_asymmetric", "standard",
      {drive(0, -0.9, -0.8), drive(1, 0.25, -0.8), drive(2, 1.1, -0.55), drive(3, 1.1, 0.75), drive(4, 0.1, 0.75),
       drive(5, -0.9, 0.6)});
  return robots;
}

}  // namespace test
}  // namespace thorvald_base
