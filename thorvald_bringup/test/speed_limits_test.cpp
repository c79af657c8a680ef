// Every robot file this package ships (and thorvald_base's figure 5 robot) under base_driver's speed limits: random
// commands, up to 1000 m/s, never drive a wheel past its drive's limit, and where the geometry can perform a command
// the executed twist is that command scaled by one common factor (the centre of rotation stays where it was put).
#include <gtest/gtest.h>
#include <thorvald_base/testing/ideal_base.h>
#include <thorvald_base/robot_config.h>
#include <thorvald_base/speed_limiter.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

using namespace thorvald_base;

namespace {

double norm(const Twist2D& t) { return std::sqrt(t.vx * t.vx + t.vy * t.vy + t.wz * t.wz); }

std::vector<std::string> robotFiles() {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(BRINGUP_CONFIG_DIR))
    if (e.path().extension() == ".yaml") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  files.push_back(std::string(BASE_CONFIG_DIR) + "/figure5.yaml");
  return files;
}

}  // namespace

TEST(SpeedLimits, EveryShippedRobotKeepsItsWheelsInLimitAndTheCommandedCentreOfRotation) {
  const std::vector<std::string> files = robotFiles();
  ASSERT_GE(files.size(), 10u) << "robot files in " << BRINGUP_CONFIG_DIR;
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> lin(-4.0, 4.0), ang(-6.0, 6.0), unit(0.0, 1.0);
  for (const std::string& path : files) {
    SCOPED_TRACE(path);
    const RobotConfig config = loadRobotConfigFile(path);
    RobotConfig unlimited_config = config;
    for (auto& d : unlimited_config.drives) d.prp_max_rpm = 0.0;  // no wheel limit: what the geometry asks for
    auto driver = idealDriver(config);
    auto unlimited = idealDriver(unlimited_config);
    double t = 0.0, t_free = 0.0;
    int feasible = 0, saturated = 0;
    for (int n = 0; n < 60; ++n) {
      // Mostly large commands (1000 m/s among them), some small ones.
      const double scale = n == 0 ? 250.0 : (unit(rng) < 0.2 ? 0.05 : 1.0);
      const Twist2D cmd{scale * lin(rng), scale * lin(rng), scale * ang(rng)};
      const Twist2D wanted = driver->calculator().achievable(cmd);
      const Twist2D free = performedTwist(*unlimited, cmd, &t_free);
      const Twist2D done = performedTwist(*driver, cmd, &t);
      for (size_t i = 0; i < config.drives.size(); ++i) {
        EXPECT_LE(std::fabs(driver->commands()[i].wheel_speed_radps), maxWheelSpeed(config.drives[i]) * (1 + 1e-9))
            << "drive" << i;
      }
      // Only where the geometry (steering limits) can perform the command is the direction checked.
      if (norm(Twist2D{free.vx - wanted.vx, free.vy - wanted.vy, free.wz - wanted.wz}) > 1e-6 * (1 + norm(wanted)))
        continue;
      ++feasible;
      const double k = driver->wheelFactor();
      saturated += k < 1.0 ? 1 : 0;
      EXPECT_GT(k, 0.0);
      EXPECT_LE(k, 1.0);
      const double tol = 1e-6 * (1.0 + norm(wanted));
      EXPECT_NEAR(done.vx, k * wanted.vx, tol) << "cmd " << cmd.vx << " " << cmd.vy << " " << cmd.wz;
      EXPECT_NEAR(done.vy, k * wanted.vy, tol);
      EXPECT_NEAR(done.wz, k * wanted.wz, tol);
    }
    EXPECT_GE(feasible, 20);
    EXPECT_GE(saturated, 10);
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
