// The `ideal` profile is the simulator's sensors as they were before the `datasheet` models: the same seed gives
// bit-for-bit the same lidar scans, ultrasonic ranges, depth images and IMU readings. The expected hashes were taken
// from the code before the models were added (thorvald_sim at 80cf826).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <cstring>
#include <random>

#include "test_scene.h"
#include "thorvald_sim/camera_images.h"
#include "thorvald_sim/camera_renderer.h"
#include "thorvald_sim/sensor_config.h"
#include "thorvald_sim/sensors.h"

namespace ts = thorvald_sim;

namespace {

/// FNV-1a over the bytes of `n` values.
template <typename T>
void hashInto(uint64_t* h, const T* values, size_t n) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(values);
  for (size_t i = 0; i < n * sizeof(T); ++i) *h = (*h ^ bytes[i]) * 0x100000001b3ull;
}

constexpr uint64_t kFnvStart = 0xcbf29ce484222325ull;

/// The greenhouse robot's sensors in the `ideal` profile, as a sensor file states them.
std::vector<ts::SensorConfig> idealSensors() {
  return ts::parseSensorConfig(YAML::Load(R"(
realism: ideal
sensors:
  - {type: lidar, name: laser, samples: 1081}
  - {type: ultrasonic, name: us, realism: ideal}
  - {type: depth_camera, name: camera, width: 160, height: 120, hfov: 1.2, range_max: 6.0}
  - {type: imu, name: imu}
)"),
                               "ideal.yaml");
}

}  // namespace

TEST(IdealProfile, LidarAndUltrasonicAreTheSameAsBefore) {
  const auto sensors = idealSensors();
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), nullptr));
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  std::mt19937 rng(11);
  uint64_t lidar = kFnvStart, us = kFnvStart;
  for (int k = 0; k < 4; ++k) {
    const auto scan =
        ts::simulateLidar(caster, ts::test::lookingAlong({-3.0 + k, 1.5, 0.6}, {1, 0.2 * k, 0}), sensors[0].lidar, rng);
    hashInto(&lidar, scan.data(), scan.size());
    ts::SensorPose down;
    down.origin = Eigen::Vector3d(-1.0 + 0.5 * k, 1.6, 0.35);
    down.rotation << 0, 0, 1, 0, 1, 0, -1, 0, 0;
    const double r = ts::simulateUltrasonic(caster, down, sensors[1].ultrasonic, rng);
    hashInto(&us, &r, 1);
  }
  EXPECT_EQ(lidar, 0x81afe34c7bd69b43ull) << std::hex << lidar;
  EXPECT_EQ(us, 0xd8572a4dc6a754d3ull) << std::hex << us;
}

TEST(IdealProfile, DepthImageIsTheSameAsBefore) {
  const auto sensors = idealSensors();
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), nullptr));
  ts::CameraRenderer renderer(w.model.get());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  const auto& spec = sensors[2].depth;
  const auto cam = ts::test::optical({-1.5, 1.6, 0.7}, {1, 0, -0.7}, {0, 0, -1});
  ts::RenderedView view;
  renderer.render(w.data.get(), cam, ts::cameraView(spec, false), -1, &view);
  std::mt19937 rng(5);
  ts::DepthImage img;
  ts::depthFromView(view, caster, cam, spec, rng, &img, 2);
  uint64_t h = kFnvStart;
  hashInto(&h, img.points.data(), img.points.size());
  EXPECT_EQ(h, 0x38b040f9132345daull) << std::hex << h;
}

TEST(IdealProfile, ImuIsTheSameAsBefore) {
  const auto sensors = idealSensors();
  ts::test::TestScene s(ts::makeFlatWorld(), {ts::test::fourWheelSteered()});
  std::mt19937 rng(3);
  uint64_t h = kFnvStart;
  for (int k = 0; k < 20; ++k) {
    s.drive(0, 0.5, 0, 0.2, 0.1);
    s.sim->updateAccelerations();
    const auto r = ts::simulateImu(s.sim->model(), s.sim->data(), s.sim->robot(0).root_body,
                                   Eigen::Matrix3d::Identity(), sensors[3].imu, rng);
    hashInto(&h, r.angular_velocity.data(), 3);
    hashInto(&h, r.linear_acceleration.data(), 3);
  }
  EXPECT_EQ(h, 0xc0a22ac0e99e76fbull) << std::hex << h;
}
