// The `realism` profile in the sensor file: parsing, refusals, and a scene whose datasheet sensors are noisier.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <random>
#include <string>

#include "test_scene.h"
#include "thorvald_sim/sensor_config.h"
#include "thorvald_sim/sensors.h"

namespace ts = thorvald_sim;

namespace {

std::string refusal(const std::string& text) {
  try {
    ts::parseSensorConfig(YAML::Load(text), "robot.yaml");
  } catch (const ts::SensorConfigError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST(RealismConfig, FileProfileWithPerSensorOverrides) {
  const auto s = ts::parseSensorConfig(YAML::Load(R"(
realism: datasheet
sensors:
  - {type: lidar, name: laser, model: {sigma_near: 0.02, mixed_probability: 0.2}}
  - {type: ultrasonic, name: us, realism: ideal}
  - {type: depth_camera, name: camera, model: {baseline: 0.07, shiny_prefix: pipe}}
  - {type: imu, name: imu, device: phidget_1044, model: {gyro_white: 0.003}}
)"),
                                       "robot.yaml");
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].lidar.realism, ts::Realism::kDatasheet);
  EXPECT_DOUBLE_EQ(s[0].lidar.model.sigma_near_m, 0.02);
  EXPECT_DOUBLE_EQ(s[0].lidar.model.mixed_probability, 0.2);
  EXPECT_DOUBLE_EQ(s[0].lidar.model.sigma_far_m, ts::LidarModel().sigma_far_m);
  EXPECT_EQ(s[1].ultrasonic.realism, ts::Realism::kIdeal);
  EXPECT_EQ(s[2].depth.realism, ts::Realism::kDatasheet);
  EXPECT_DOUBLE_EQ(s[2].depth.stereo.baseline_m, 0.07);
  EXPECT_EQ(s[2].depth.stereo.shiny_prefix, "pipe");
  EXPECT_EQ(s[3].imu.realism, ts::Realism::kDatasheet);
  EXPECT_DOUBLE_EQ(s[3].imu.model.gyro.white_sigma, 0.003);
  EXPECT_DOUBLE_EQ(s[3].imu.model.accel.white_sigma, ts::phidget1044ImuModel().accel.white_sigma);
  // Without `realism` every sensor stays ideal, with the UM7 as the IMU's device.
  const auto d = ts::parseSensorConfig(YAML::Load("sensors: [{type: imu, name: imu}]"), "t");
  EXPECT_EQ(d[0].imu.realism, ts::Realism::kIdeal);
  EXPECT_DOUBLE_EQ(d[0].imu.model.gyro.white_sigma, ts::um7ImuModel().gyro.white_sigma);
}

TEST(RealismConfig, RefusesUnknownProfilesDevicesKeysAndValuesNamingThem) {
  auto has = [](const std::string& what, const std::string& part) { return what.find(part) != std::string::npos; };
  std::string e = refusal("realism: realistic\nsensors: []");
  EXPECT_TRUE(has(e, "realism") && has(e, "'realistic'")) << e;
  e = refusal("sensors: [{type: lidar, name: l, realism: datasheeet}]");
  EXPECT_TRUE(has(e, "(l).realism") && has(e, "'datasheeet'")) << e;
  e = refusal("sensors: [{type: imu, name: i, device: mpu6050}]");
  EXPECT_TRUE(has(e, "(i).device") && has(e, "'mpu6050'") && has(e, "phidget_1044")) << e;
  e = refusal("realism: datasheet\nsensors: [{type: lidar, name: l, model: {sigma: 0.01}}]");
  EXPECT_TRUE(has(e, "(l).model.sigma") && has(e, "no such key")) << e;
  e = refusal("realism: datasheet\nsensors: [{type: lidar, name: l, model: {dropout: 1.5}}]");
  EXPECT_TRUE(has(e, "(l).model.dropout") && has(e, "1.5")) << e;
  e = refusal("sensors: [{type: depth_camera, name: c, model: {flying_probability: -0.1}}]");
  EXPECT_TRUE(has(e, "(c).model.flying_probability")) << e;
  e = refusal("sensors: [{type: imu, name: i, model: 3}]");
  EXPECT_TRUE(has(e, "(i).model") && has(e, "map")) << e;
}

TEST(RealismConfig, DatasheetSceneIsNoisierThanIdeal) {
  // The greenhouse robot on the headland facing the rear wall, driving slowly, with the lidar and IMU of one sensor
  // file in each profile: against the noise-free scan and the true IMU reading, the datasheet errors are larger.
  const char* file = R"(
sensors:
  - {type: lidar, name: laser, xyz: [0.45, 0.0, 0.62], samples: 1081}
  - {type: imu, name: imu, xyz: [0.0, 0.0, 0.5]}
)";
  YAML::Node ideal_yaml = YAML::Load(file), datasheet_yaml = YAML::Load(file);
  datasheet_yaml["realism"] = "datasheet";
  const auto ideal = ts::parseSensorConfig(ideal_yaml, "ideal");
  const auto datasheet = ts::parseSensorConfig(datasheet_yaml, "datasheet");
  ts::GreenhouseTruth truth;
  ts::test::TestScene s(ts::makeGreenhouseWorld(ts::GreenhouseParams(), &truth), {ts::test::fourWheelSteered()},
                        {{{truth.rear_wall_x + 4.0, 2.0, M_PI}}});
  const int body = s.sim->robot(0).root_body;
  std::mt19937 rng(1);
  ts::ImuErrors errors(datasheet[1].imu.model, rng);
  ts::LidarSpec exact = ideal[0].lidar;
  exact.noise_m = 0.0;
  double lidar_sq[2] = {0, 0}, accel_sq[2] = {0, 0};
  int lidar_n[2] = {0, 0}, lost[2] = {0, 0}, imu_n = 0;
  for (int k = 0; k < 40; ++k) {
    s.drive(0, 0.05, 0, 0, 0.1);
    s.sim->updateAccelerations();
    ts::SensorPose pose;
    const ts::BodyState b = s.sim->robotState(0);
    pose.origin = b.position + b.orientation * Eigen::Vector3d(0.45, 0, 0.62);
    pose.rotation = b.orientation.toRotationMatrix();
    ts::RayCaster caster(s.sim->model(), s.sim->data(), body);
    const auto want = ts::simulateLidar(caster, pose, exact, rng);
    const ts::SensorConfig* cfg[2] = {&ideal[0], &datasheet[0]};
    for (int p = 0; p < 2; ++p) {
      const auto scan = ts::simulateLidar(caster, pose, cfg[p]->lidar, rng);
      for (size_t i = 0; i < want.size(); ++i) {
        if (!std::isfinite(want[i])) continue;
        if (!std::isfinite(scan[i])) {
          ++lost[p];
          continue;
        }
        lidar_sq[p] += (scan[i] - want[i]) * (scan[i] - want[i]), ++lidar_n[p];
      }
    }
    ts::ImuSpec still = ideal[1].imu;
    still.accel_noise_mps2 = still.gyro_noise_radps = 0.0;
    const auto truth_imu =
        ts::simulateImu(s.sim->model(), s.sim->data(), body, Eigen::Matrix3d::Identity(), still, rng);
    const auto a = ts::simulateImu(s.sim->model(), s.sim->data(), body, Eigen::Matrix3d::Identity(), ideal[1].imu, rng);
    const auto d = ts::simulateImu(s.sim->model(), s.sim->data(), body, Eigen::Matrix3d::Identity(), datasheet[1].imu,
                                   rng, &errors, s.t);
    accel_sq[0] += (a.linear_acceleration - truth_imu.linear_acceleration).squaredNorm();
    accel_sq[1] += (d.linear_acceleration - truth_imu.linear_acceleration).squaredNorm();
    ++imu_n;
  }
  const double lidar_rms[2] = {std::sqrt(lidar_sq[0] / lidar_n[0]), std::sqrt(lidar_sq[1] / lidar_n[1])};
  EXPECT_GT(lidar_rms[1], 1.2 * lidar_rms[0]) << lidar_rms[0] << " vs " << lidar_rms[1];
  EXPECT_EQ(lost[0], 0);
  EXPECT_GT(lost[1], 0);
  EXPECT_GT(std::sqrt(accel_sq[1] / imu_n), 1.2 * std::sqrt(accel_sq[0] / imu_n));
}
