// Ray-cast sensors see the worlds' known geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "test_scene.h"
#include "thorvald_sim/sensors.h"
#include "thorvald_sim/world.h"

namespace ts = thorvald_sim;
using ts::test::optical;
using ts::test::StaticWorld;

namespace {

// Sensor looking along `x_axis` (its x) with `z_axis` up.
ts::SensorPose pose(const Eigen::Vector3d& origin, const Eigen::Vector3d& x_axis, const Eigen::Vector3d& z_axis) {
  ts::SensorPose p;
  p.origin = origin;
  p.rotation.col(0) = x_axis.normalized();
  p.rotation.col(2) = z_axis.normalized();
  p.rotation.col(1) = p.rotation.col(2).cross(p.rotation.col(0));
  return p;
}

}  // namespace

TEST(Lidar, RangeToTheRearWall) {
  ts::GreenhouseTruth truth;
  StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), &truth));
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::LidarSpec spec;
  spec.noise_m = 0.0;
  std::mt19937 rng(1);
  // At x = -3 on the headland, 0.6 m up, facing the rear wall (-x): the middle beam hits its face at x = rear_x.
  const auto scan = ts::simulateLidar(caster, pose({-3.0, 2.0, 0.6}, {-1, 0, 0}, {0, 0, 1}), spec, rng);
  ASSERT_EQ(scan.size(), 541u);
  EXPECT_NEAR(scan[270], -3.0 - truth.rear_wall_x, 1e-6);
  // A beam 30 degrees off the axis meets the same plane at 3 / cos(30 deg).
  const int k = 270 + static_cast<int>(std::lround((M_PI / 6) / ((spec.angle_max_rad - spec.angle_min_rad) / 540)));
  const double a = spec.angle_min_rad + k * (spec.angle_max_rad - spec.angle_min_rad) / 540;
  EXPECT_NEAR(scan[k], (-3.0 - truth.rear_wall_x) / std::cos(a), 1e-6);
}

TEST(Lidar, NoiseHasTheStatedSpread) {
  StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), nullptr));
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::LidarSpec spec;
  spec.noise_m = 0.02;
  std::mt19937 rng(7);
  double sum = 0, sq = 0;
  const int n = 40;
  for (int i = 0; i < n; ++i) {
    const double e = ts::simulateLidar(caster, pose({-3.0, 2.0, 0.6}, {-1, 0, 0}, {0, 0, 1}), spec, rng)[270] - 3.0;
    sum += e, sq += e * e;
  }
  const double mean = sum / n, sd = std::sqrt(sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.012);  // 4 sigma of the mean of 40 draws: 4 * 0.02 / sqrt(40)
  EXPECT_NEAR(sd, 0.02, 0.008);
}

TEST(Ultrasonic, ConeReportsTheNearestEcho) {
  ts::GreenhouseTruth t;
  StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), &t));
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::UltrasonicSpec spec;
  spec.noise_m = 0.0;
  spec.fov_rad = 0.5;
  std::mt19937 rng(1);
  // 0.3 m up and 5 cm beyond the edge over the rows' ground: the axis sees the ground 0.45 m down, but the cone
  // (half angle 0.25 rad reaches 7.7 cm back at the floor's height) also covers the headland floor 0.3 m down.
  const double got =
      ts::simulateUltrasonic(caster, pose({0.05, t.rail_sets[1].start_y, 0.3}, {0, 0, -1}, {1, 0, 0}), spec, rng);
  EXPECT_LT(got, 0.3 / std::cos(0.25) + 1e-6);
  EXPECT_GE(got, 0.3 - 1e-6);
  spec.fov_rad = 0.1;  // a narrow cone does not reach back to the edge
  EXPECT_NEAR(
      ts::simulateUltrasonic(caster, pose({0.05, t.rail_sets[1].start_y, 0.3}, {0, 0, -1}, {1, 0, 0}), spec, rng), 0.45,
      1e-6);
}

TEST(Ultrasonic, FloorRailAndEdge) {
  ts::GreenhouseTruth t;
  StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), &t));
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::UltrasonicSpec spec;
  spec.noise_m = 0.0;
  std::mt19937 rng(1);
  const Eigen::Vector3d down(0, 0, -1), fwd(1, 0, 0);
  const double h = 0.3;
  // On the headland: the floor at z = 0.
  EXPECT_NEAR(ts::simulateUltrasonic(caster, pose({-1.0, 0.0, h}, down, fwd), spec, rng), h, 1e-6);
  // Over a pipe of rail set 1, 5 m along the row: its top at rail_top.
  const double pipe_y = t.rail_sets[1].pipe_y[0];
  EXPECT_NEAR(ts::simulateUltrasonic(caster, pose({5.0, pipe_y, h}, down, fwd), spec, rng), h - t.params.rail_top_m,
              1e-6);
  // Past the edge, between the pipes of set 1: the rows' ground, row_ground_drop below the floor.
  EXPECT_NEAR(ts::simulateUltrasonic(caster, pose({0.3, t.rail_sets[1].start_y, h}, down, fwd), spec, rng),
              h + t.params.row_ground_drop_m, 1e-6);
  // Nothing within range_max: +inf.
  spec.range_max_m = 0.2;
  EXPECT_TRUE(std::isinf(ts::simulateUltrasonic(caster, pose({-1.0, 0.0, h}, down, fwd), spec, rng)));
}

TEST(DepthCamera, PipePointsLieOnThePipes) {
  ts::GreenhouseTruth t;
  StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), &t));
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::DepthCameraSpec spec;
  spec.width = 160;
  spec.height = 120;
  spec.noise_coeff = 0.0;
  spec.dropout = 0.0;
  std::mt19937 rng(1);
  const auto& set = t.rail_sets[2];
  const auto cam = optical({-1.2, set.start_y, 0.8}, {1.0, 0.0, -0.6}, {0, 0, -1});
  const auto img = ts::simulateDepth(caster, cam, spec, rng);
  ASSERT_EQ(img.points.size(), 160u * 120u);
  int on_pipe = 0, valid = 0;
  const double r = 0.5 * t.params.pipe_diameter_m;
  for (const auto& p : img.points) {
    if (!std::isfinite(p.z())) continue;
    ++valid;
    const Eigen::Vector3d wp = cam.origin + cam.rotation * p.cast<double>();
    if (wp.z() < t.floor_z + 0.01 || wp.x() < set.start_x || wp.x() > 6.0) continue;  // above the floor level
    if (std::fabs(wp.y() - set.start_y) > 0.5) continue;
    ++on_pipe;
    // Every such point is on the surface of one of the two pipes (capsules: rounded at their start).
    const double dy = std::min(std::fabs(wp.y() - set.pipe_y[0]), std::fabs(wp.y() - set.pipe_y[1]));
    const double dx = std::max(0.0, set.start_x + r - wp.x());
    EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + std::pow(wp.z() - t.pipe_centre_z, 2)), r, 1e-4) << wp.transpose();
  }
  EXPECT_GT(valid, 160 * 120 / 2);
  EXPECT_GT(on_pipe, 20);
}

TEST(DepthCamera, NoiseGrowsWithDepthAndDropoutsHappen) {
  StaticWorld w(ts::makeFlatWorld());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::DepthCameraSpec spec;
  spec.width = 64;
  spec.height = 48;
  spec.noise_coeff = 0.005;
  spec.dropout = 0.1;
  std::mt19937 rng(3);
  // Looking straight down from 2 m: true z = 2 everywhere; sd = 0.005 * 4 = 0.02.
  const auto img = ts::simulateDepth(caster, optical({0, 0, 2.0}, {0, 0, -1}, {1, 0, 0}), spec, rng);
  double sum = 0, sq = 0;
  int n = 0;
  for (const auto& p : img.points)
    if (std::isfinite(p.z())) sum += p.z() - 2.0, sq += (p.z() - 2.0) * (p.z() - 2.0), ++n;
  const double mean = sum / n, sd = std::sqrt(sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.003);
  EXPECT_NEAR(sd, 0.02, 0.003);
  EXPECT_NEAR(1.0 - n / (64.0 * 48.0), 0.1, 0.03);  // dropouts: 10 % +- 3 %
}

TEST(ColorCamera, BollPixelIsWhite) {
  ts::CottonRowTruth t;
  StaticWorld w(ts::makeCottonRowWorld(ts::CottonRowParams(), &t));
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::ColorCameraSpec spec;
  spec.width = 64;
  spec.height = 48;
  // Looking at the highest boll of plant 3 from 0.5 m beside it: its centre projects to the image centre.
  int best = -1;
  for (size_t i = 0; i < t.bolls.size(); ++i)
    if (t.boll_plant[i] == 3 && (best < 0 || t.bolls[i].z() > t.bolls[best].z())) best = static_cast<int>(i);
  ASSERT_GE(best, 0);
  const Eigen::Vector3d boll = t.bolls[best];
  const auto cam = optical(boll + Eigen::Vector3d(0, 0, 0.5), {0, 0, -1}, {1, 0, 0});
  const auto img = ts::simulateColor(caster, w.model.get(), cam, spec);
  const auto k = ts::intrinsics(64, 48, spec.hfov_rad);
  const int u = static_cast<int>(std::lround(k.cx)), v = static_cast<int>(std::lround(k.cy));
  const uint8_t* px = &img.rgb[(v * 64 + u) * 3];
  EXPECT_EQ(px[0], 255);
  EXPECT_EQ(px[1], 255);
  EXPECT_EQ(px[2], 255);
  // A corner pixel sees the soil or leaves: not white.
  const uint8_t* corner = &img.rgb[0];
  EXPECT_FALSE(corner[0] == 255 && corner[1] == 255 && corner[2] == 255);
}

TEST(Imu, AtRestReadsGravityReaction) {
  ts::test::TestScene s(ts::makeFlatWorld(), {ts::test::fourWheelSteered()});
  s.drive(0, 0, 0, 0, 1.0);
  s.sim->updateAccelerations();
  std::mt19937 rng(1);
  ts::ImuSpec spec;
  spec.accel_noise_mps2 = spec.gyro_noise_radps = 0.0;
  const auto r =
      ts::simulateImu(s.sim->model(), s.sim->data(), s.sim->robot(0).root_body, Eigen::Matrix3d::Identity(), spec, rng);
  EXPECT_NEAR(r.linear_acceleration.z(), 9.81, 0.05);
  EXPECT_NEAR(r.linear_acceleration.head<2>().norm(), 0.0, 0.05);
  EXPECT_NEAR(r.angular_velocity.norm(), 0.0, 1e-3);
}

TEST(Lidar, DoesNotSeeItsOwnRobotButSeesOthers) {
  // Two robots 3 m apart on the flat world; a lidar inside robot 0's frame box sees robot 1 but not itself.
  ts::test::TestScene s(ts::makeFlatWorld(), {ts::test::fourWheelSteered(), ts::test::fourWheelSteered()},
                        {{{0, 0, 0}}, {{3.0, 0, 0}}});
  s.drive(0, 0, 0, 0, 0.5);
  ts::RayCaster own(s.sim->model(), s.sim->data(), s.sim->robot(0).root_body);
  ts::LidarSpec spec;
  spec.noise_m = 0;
  spec.samples = 3;
  spec.angle_min_rad = -0.01;
  spec.angle_max_rad = 0.01;
  std::mt19937 rng(1);
  // At the height of the frame box (z = 2 r + 0.15 = 0.55): robot 1's box starts at 3 - 0.675 - (half length).
  const auto scan = ts::simulateLidar(own, pose({0, 0, 0.55}, {1, 0, 0}, {0, 0, 1}), spec, rng);
  EXPECT_NEAR(scan[1], 3.0 - 0.675, 0.02);
}

TEST(Lidar, BeamSectorsGiveTheScanOfTestingEveryGeom) {
  // Beam-sector culling must not change a single range: compare with every prepared geom tested for every beam,
  // from several places and headings in the greenhouse (between the pipes, on the headland, near a wall, tilted).
  StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), nullptr));
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::LidarSpec spec;
  spec.samples = 1081;
  spec.noise_m = 0.0;
  std::mt19937 rng(1);
  const std::vector<ts::SensorPose> poses = {
      pose({-3.0, 2.0, 0.6}, {-1, 0, 0}, {0, 0, 1}), pose({4.0, 1.6, 0.3}, {1, 0.1, 0}, {0, 0, 1}),
      pose({-5.5, -0.9, 0.45}, {0.3, 1, 0}, {0, 0, 1}), pose({2.0, 3.2, 0.5}, {1, 0, -0.2}, {0.2, 0, 1})};
  for (const auto& p : poses) {
    const auto scan = ts::simulateLidar(caster, p, spec, rng);
    caster.prepare(p.origin, spec.range_max_m, p.rotation.col(0), M_PI);
    const double inc = (spec.angle_max_rad - spec.angle_min_rad) / (spec.samples - 1);
    int hits = 0;
    for (int i = 0; i < spec.samples; ++i) {
      const double a = spec.angle_min_rad + i * inc;
      const double d = caster.cast(p.origin, p.rotation * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0));
      const float want = (d >= spec.range_min_m && d <= spec.range_max_m) ? static_cast<float>(d)
                                                                          : std::numeric_limits<float>::infinity();
      ASSERT_EQ(scan[i], want) << "beam " << i;
      hits += std::isfinite(want) ? 1 : 0;
    }
    EXPECT_GT(hits, 500);
  }
}
