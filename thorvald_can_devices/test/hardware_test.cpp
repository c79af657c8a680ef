// BaseDriver on the CAN hardware and the simulated devices: the whole chain without ROS.
#include <gtest/gtest.h>

#include <cmath>

#include "rig.h"
#include "thorvald_base/base_driver.h"
#include "thorvald_base/standard_calculator.h"

using namespace thorvald_can_devices;

namespace {

TEST(BaseOnCan, DrivesStraightAndStopsWithin100msWhenADriveGoesSilent) {
  Rig rig("robots/4wd4ws.yaml");
  rig.run(0.3);
  thorvald_base::BaseDriver driver(rig.config, std::make_unique<thorvald_base::StandardCalculator>(),
                                   std::move(rig.drives), std::move(rig.batteries), {});
  const auto cycle = [&] {
    for (int k = 0; k < 10; ++k) {
      rig.t += 0.002;
      rig.sim.spinOnce(rig.t, *rig.sim_bus);
    }
    rig.hw.poll(rig.t);
    driver.update(rig.t);
  };
  for (int i = 0; i < 150; ++i) {
    driver.setCommand({0.5, 0.0, 0.0}, rig.t);
    cycle();
  }
  EXPECT_NEAR(driver.velocity().twist.vx, 0.5, 0.005);
  EXPECT_NEAR(driver.velocity().twist.wz, 0.0, 0.005);
  // 3 s at 0.5 m/s less the ramp at 1.5 m/s^2 (0.33 s): 1.5 - 0.083 = 1.417 m, within a cycle of lag.
  EXPECT_NEAR(driver.odometry().pose().x, 1.417, 0.03);
  ASSERT_TRUE(rig.inject("drive2", "silent", true));
  int cycles = 0;
  while (!driver.driveStop() && cycles < 200) {
    driver.setCommand({0.5, 0.0, 0.0}, rig.t);
    cycle();
    ++cycles;
  }
  ASSERT_TRUE(driver.driveStop());
  EXPECT_EQ(driver.driveStopText().rfind("drive2: lost (no feedback for ", 0), 0u) << driver.driveStopText();
  EXPECT_LE(cycles * 0.02, 0.1 + 1e-9);  // feedback timeout (60 ms) plus at most two cycles
  // In that same cycle every remaining drive got a zero propulsion command.
  for (size_t i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(driver.commands()[i].wheel_speed_radps, 0.0);
  std::string why;
  EXPECT_FALSE(driver.clearDriveStop(&why));
  ASSERT_TRUE(rig.inject("drive2", "silent", false));
  for (int i = 0; i < 50; ++i) cycle();
  EXPECT_TRUE(driver.clearDriveStop(&why)) << why;
}

}  // namespace
