// Every kinematics plugin name a robot file may use resolves through pluginlib and drives its robot.
#include <gtest/gtest.h>
#include <pluginlib/class_loader.hpp>
#include <ros/ros.h>

#include "test_robots.h"
#include "thorvald_base/base_calculator.h"

using namespace thorvald_base;

TEST(Plugins, EveryNameLoadsAndDrives) {
  pluginlib::ClassLoader<BaseCalculator> loader("thorvald_base", "thorvald_base::BaseCalculator");
  const auto robots = test::paperRobots();
  struct Case {
    const char* name;
    size_t robot;
    const char* type;
  };
  const Case cases[] = {
      {"pltf_clc_std::PltfClcStd", 0, "thorvald_base::StandardCalculator"},
      {"pltf_clc_2wdiff::PltfClc2WDiff", 4, "thorvald_base::DiffDriveCalculator"},
      {"thorvald_base/StandardCalculator", 7, "thorvald_base::StandardCalculator"},
      {"thorvald_base/DiffDriveCalculator", 4, "thorvald_base::DiffDriveCalculator"},
      {"thorvald_base/OneWheelCalculator", 3, "thorvald_base::OneWheelCalculator"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    std::unique_ptr<BaseCalculator> calc(loader.createUnmanagedInstance(c.name));
    ASSERT_TRUE(calc);
    EXPECT_EQ(calc->name(), c.type);
    const auto& robot = robots[c.robot].config;
    calc->configure(robot.drives, robot.passive_wheels, {});
    std::vector<DriveCommand> prev(robot.drives.size());
    std::vector<DriveFeedback> fb(robot.drives.size());
    for (auto& f : fb) f.valid = true;
    const auto out = calc->computeCommands({0.4, 0.0, 0.0}, fb, prev);
    for (const auto& cmd : out) EXPECT_NEAR(cmd.wheel_speed_radps, 0.4 / 0.2, 1e-9);
  }
  EXPECT_THROW(loader.createUnmanagedInstance("no_such::Plugin"), pluginlib::PluginlibException);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "plugin_loading_test");
  return RUN_ALL_TESTS();
}
