#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "thorvald_sim/sensor_config.h"

namespace ts = thorvald_sim;

TEST(SensorConfig, ParsesEveryType) {
  const auto s = ts::parseSensorConfig(YAML::Load(R"(
sensors:
  - {type: lidar, name: laser, xyz: [0.5, 0, 0.6], rate: 20, samples: 1081, noise: 0.005}
  - {type: ultrasonic, name: front_left, xyz: [0.6, 0.3, 0.3], rpy: [0, 1.5708, 0], fov: 0.4, range_max: 1.5}
  - {type: depth_camera, name: camera, width: 320, height: 240, hfov: 1.2, color: true, rate: 30}
  - {type: imu, name: imu, rate: 100}
)"),
                                       "test");
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].type, ts::SensorType::kLidar);
  EXPECT_EQ(s[0].topic, "scan");
  EXPECT_EQ(s[0].lidar.samples, 1081);
  EXPECT_DOUBLE_EQ(s[0].rate_hz, 20.0);
  EXPECT_EQ(s[1].topic, "ultrasonic/front_left");
  EXPECT_NEAR((s[1].mountRotation() * Eigen::Vector3d::UnitX() - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-4);
  EXPECT_TRUE(s[2].color);
  EXPECT_EQ(s[2].depth.width, 320);
  EXPECT_EQ(s[3].type, ts::SensorType::kImu);
  EXPECT_TRUE(ts::parseSensorConfig(YAML::Load("sensors: []"), "t").empty());
  EXPECT_TRUE(ts::parseSensorConfig(YAML::Node(), "t").empty());
}

TEST(SensorConfig, ErrorsNameSensorAndKey) {
  auto message = [](const char* text) {
    try {
      ts::parseSensorConfig(YAML::Load(text), "robot.yaml");
    } catch (const ts::SensorConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("sensors: [{type: lidar, name: l, samples: -3}]").find("(l).samples"), std::string::npos);
  EXPECT_NE(message("sensors: [{type: radar, name: r}]").find("type"), std::string::npos);
  EXPECT_NE(message("sensors: [{type: lidar, name: l, smaples: 3}]").find("smaples"), std::string::npos);
  EXPECT_NE(message("sensors: [{type: imu, name: a}, {type: imu, name: a}]").find("twice"), std::string::npos);
  EXPECT_NE(message("sensors: [{type: lidar, name: l, xyz: [1, 2]}]").find("xyz"), std::string::npos);
  EXPECT_NE(message("sensors: {type: lidar}").find("list"), std::string::npos);
}
