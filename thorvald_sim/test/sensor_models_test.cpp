// The datasheet models of the lidar, the IMU and the ultrasonic range finder against their formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "test_scene.h"
#include "thorvald_sim/imu_model.h"
#include "thorvald_sim/lidar_model.h"
#include "thorvald_sim/sensors.h"
#include "thorvald_sim/ultrasonic_model.h"

namespace ts = thorvald_sim;

namespace {

struct Stats {
  double mean = 0, sd = 0;
  size_t n = 0;
};

Stats stats(const std::vector<double>& x) {
  Stats s;
  s.n = x.size();
  for (double v : x) s.mean += v;
  s.mean /= std::max<size_t>(1, s.n);
  for (double v : x) s.sd += (v - s.mean) * (v - s.mean);
  s.sd = std::sqrt(s.sd / std::max<size_t>(1, s.n - 1));
  return s;
}

// A lidar model with nothing but its range noise.
ts::LidarModel noiseOnly() {
  ts::LidarModel m;
  m.dropout = 0.0;
  m.mixed_probability = 0.0;
  return m;
}

}  // namespace

TEST(LidarModel, RangeNoiseFollowsTheDatasheetAtThreeRanges) {
  const ts::LidarModel m = noiseOnly();
  std::mt19937 rng(1);
  for (double range : {2.0, 8.0, 20.0}) {
    const std::vector<ts::LidarBeam> beams(20000, {range, 0.0});
    const auto scan = ts::applyLidarModel(beams, 0.1, 30.0, m, rng);
    std::vector<double> r(scan.begin(), scan.end());
    const Stats s = stats(r);
    EXPECT_NEAR(s.sd, ts::lidarSigma(m, range), 0.1 * ts::lidarSigma(m, range)) << range;
    EXPECT_NEAR(s.mean, range, 4 * s.sd / std::sqrt(s.n)) << range;
  }
  EXPECT_DOUBLE_EQ(ts::lidarSigma(m, 8.0), 0.010);
  EXPECT_DOUBLE_EQ(ts::lidarSigma(m, 20.0), 0.025);
}

TEST(LidarModel, DropoutsAndGlancingBeamsReturnNothing) {
  ts::LidarModel m = noiseOnly();
  m.dropout = 0.1;
  std::mt19937 rng(2);
  const int n = 40000;
  const auto scan = ts::applyLidarModel(std::vector<ts::LidarBeam>(n, {5.0, 0.3}), 0.1, 30.0, m, rng);
  int lost = 0;
  for (float r : scan) lost += std::isinf(r);
  EXPECT_NEAR(lost / double(n), 0.1, 0.006);  // 4 binomial sigma of 40000 draws: 0.006
  m.dropout = 0.0;
  const auto glancing =
      ts::applyLidarModel({{5.0, m.max_incidence_rad - 0.01}, {5.0, m.max_incidence_rad + 0.01}}, 0.1, 30.0, m, rng);
  EXPECT_TRUE(std::isfinite(glancing[0]));
  EXPECT_TRUE(std::isinf(glancing[1]));
}

TEST(LidarModel, GlancingReturnsLostByRangeAsTheirPowerFalls) {
  // A matte surface returns while reflectance cos(incidence) >= (range / white_range)^2: at 5, 10 and 20 m of the
  // white sheet's 30 m the limit is acos(1/36) (capped at max_incidence), acos(1/9) and acos(4/9).
  ts::LidarModel m;
  m.dropout = 0.0, m.mixed_probability = 0.0, m.sigma_near_m = m.sigma_far_m = 0.0;
  std::mt19937 rng(12);
  for (double range : {5.0, 10.0, 20.0}) {
    const double r = range / m.white_range_m;
    const double limit = std::min(m.max_incidence_rad, std::acos(r * r / m.reflectance));
    EXPECT_TRUE(ts::lidarReturns(m, range, limit - 0.01)) << range;
    EXPECT_FALSE(ts::lidarReturns(m, range, limit + 0.01)) << range;
    const auto out = ts::applyLidarModel({{range, limit - 0.01}, {range, limit + 0.01}}, 0.1, 30.0, m, rng);
    EXPECT_TRUE(std::isfinite(out[0])) << range;
    EXPECT_TRUE(std::isinf(out[1])) << range;
  }
  m.reflectance = 0.25;  // a dark surface: nothing beyond 15 m even head-on
  EXPECT_TRUE(ts::lidarReturns(m, 14.9, 0.0));
  EXPECT_FALSE(ts::lidarReturns(m, 15.1, 0.0));
}

TEST(LidarModel, MixedPixelOnAKnownEdge) {
  // Beams 0-9 on a post 2 m away, 10-19 on the wall 5 m behind it: the post's last beam straddles the edge.
  ts::LidarModel m = noiseOnly();
  m.sigma_near_m = m.sigma_far_m = 0.001;
  m.mixed_probability = 0.3;
  std::vector<ts::LidarBeam> beams(20, {5.0, 0.0});
  for (int i = 0; i < 10; ++i) beams[i].range_m = 2.0;
  std::mt19937 rng(3);
  int mixed = 0, elsewhere = 0;
  const int scans = 4000;
  for (int k = 0; k < scans; ++k) {
    const auto scan = ts::applyLidarModel(beams, 0.1, 30.0, m, rng);
    for (int i = 0; i < 20; ++i) {
      const bool between = scan[i] > 2.01 && scan[i] < 4.99;
      (i == 9 ? mixed : elsewhere) += between;
    }
  }
  EXPECT_NEAR(mixed / double(scans), 0.3, 0.03);  // 4 binomial sigma: 0.029
  EXPECT_EQ(elsewhere, 0);
}

TEST(LidarModel, SweepTakesEachBeamFromItsOwnPose) {
  // Facing the rear wall 3 m away and moving towards it 0.5 m over one mirror turn: the beam at angle a is taken a
  // fraction (a - angle_min) / 2 pi into the turn, nearer by 0.5 m times that fraction.
  ts::GreenhouseTruth truth;
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), &truth));
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::LidarSpec spec;
  spec.realism = ts::Realism::kDatasheet;
  spec.model = noiseOnly();
  spec.model.sigma_near_m = spec.model.sigma_far_m = 0.0;
  const ts::SensorPose start = ts::test::lookingAlong({truth.rear_wall_x + 3.0, 2.0, 0.6}, {-1, 0, 0});
  ts::SensorPose end = start;
  end.origin.x() -= 0.5;
  std::mt19937 rng(4);
  const auto still = ts::simulateLidar(caster, start, spec, rng);
  const auto moving = ts::simulateLidar(caster, start, spec, rng, &end);
  const int mid = spec.samples / 2;
  const double f = (0.0 - spec.angle_min_rad) / (2 * M_PI);
  EXPECT_NEAR(still[mid], 3.0, 1e-6);
  EXPECT_NEAR(moving[mid], 3.0 - 0.5 * f, 1e-6);
  const int k = mid + 57;  // about 0.5 rad to the left, later in the turn
  const double inc = (spec.angle_max_rad - spec.angle_min_rad) / (spec.samples - 1);
  const double a = spec.angle_min_rad + k * inc, fk = (a - spec.angle_min_rad) / (2 * M_PI);
  EXPECT_NEAR(moving[k], (3.0 - 0.5 * fk) / std::cos(a), 1e-6);
}

TEST(LidarModel, GlancingWallIsLostInTheDatasheetProfileOnly) {
  // Along the rear wall, 0.5 m from it: beams that meet it beyond the incidence limit return nothing.
  ts::GreenhouseTruth truth;
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), &truth));
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::LidarSpec spec;
  spec.noise_m = 0.0;
  std::mt19937 rng(5);
  const ts::SensorPose pose =
      ts::test::lookingAlong({truth.rear_wall_x + 0.5, 2.0, 0.6}, {0, 1, 0});  // wall on the left (-x)
  const auto ideal = ts::simulateLidar(caster, pose, spec, rng);
  spec.realism = ts::Realism::kDatasheet;
  spec.model = noiseOnly();
  spec.model.max_incidence_rad = 1.0;
  const auto datasheet = ts::simulateLidar(caster, pose, spec, rng);
  const double inc = (spec.angle_max_rad - spec.angle_min_rad) / (spec.samples - 1);
  // The wall is at the sensor's +90 deg (its y axis is world -x): a beam at angle a meets it at incidence |a - 90 deg|.
  int lost = 0, kept = 0;
  for (int i = 0; i < spec.samples; ++i) {
    const double a = spec.angle_min_rad + i * inc, incidence = std::fabs(a - M_PI / 2);
    if (a < 0.3 || !std::isfinite(ideal[i]) || std::fabs(ideal[i] - 0.5 / std::cos(incidence)) > 1e-3) continue;
    if (incidence > spec.model.max_incidence_rad + 0.01) {
      EXPECT_TRUE(std::isinf(datasheet[i])) << a;
      ++lost;
    }
    if (incidence < spec.model.max_incidence_rad - 0.01) {
      EXPECT_TRUE(std::isfinite(datasheet[i])) << a;
      ++kept;
    }
  }
  EXPECT_GT(lost, 10);
  EXPECT_GT(kept, 10);
}

TEST(ImuModel, WhiteNoiseAndScaleFactor) {
  ts::ImuModel m;
  m.gyro.white_sigma = 0.003;
  m.accel.white_sigma = 0.05;
  std::mt19937 rng(6);
  ts::ImuErrors e(m, rng);
  std::vector<double> g, a;
  for (int k = 0; k < 20000; ++k) {
    Eigen::Vector3d gyro(0.1, 0, 0), accel(0, 0, 9.81);
    e.apply(0.01 * k, &gyro, &accel, rng);
    g.push_back(gyro.x()), a.push_back(accel.z());
  }
  EXPECT_NEAR(stats(g).sd, 0.003, 0.0003);
  EXPECT_NEAR(stats(a).sd, 0.05, 0.005);
  EXPECT_NEAR(stats(g).mean, 0.1, 1e-4);  // no scale error, no bias
  // Scale factors: drawn once per sensor, spread scale_factor_sigma over many sensors.
  ts::ImuModel s;
  s.gyro.scale_factor_sigma = 0.01;
  std::vector<double> scales;
  for (int k = 0; k < 3000; ++k) {
    ts::ImuErrors one(s, rng);
    Eigen::Vector3d gyro(1.0, 0, 0), accel(0, 0, 0);
    one.apply(0.0, &gyro, &accel, rng);
    scales.push_back(gyro.x());
  }
  EXPECT_NEAR(stats(scales).sd, 0.01, 0.001);
  EXPECT_NEAR(stats(scales).mean, 1.0, 0.001);
}

TEST(ImuModel, BiasDriftGrowsAsGaussMarkovPlusRandomWalk) {
  // Over many sensors, Var(b(t) - b(0)) = 2 s^2 (1 - exp(-t / tau)) + q^2 t.
  ts::ImuModel m;
  m.gyro.bias_instability = 0.001;
  m.gyro.bias_correlation_s = 100.0;
  m.gyro.bias_random_walk = 2e-4;
  std::mt19937 rng(7);
  const std::vector<double> times = {10.0, 100.0, 500.0};
  std::vector<std::vector<double>> drift(times.size());
  for (int k = 0; k < 2000; ++k) {
    ts::ImuErrors e(m, rng);
    const double b0 = e.gyroBias().x();
    double t = 0.0;
    Eigen::Vector3d g, a;
    e.apply(t, &g, &a, rng);
    for (size_t i = 0; i < times.size(); ++i) {
      while (t < times[i] - 1e-9) {
        t += 1.0;
        e.apply(t, &g, &a, rng);
      }
      drift[i].push_back(e.gyroBias().x() - b0);
    }
  }
  for (size_t i = 0; i < times.size(); ++i) {
    const double want = 2 * 1e-6 * (1 - std::exp(-times[i] / 100.0)) + 4e-8 * times[i];
    const double sd = stats(drift[i]).sd;
    EXPECT_NEAR(sd * sd, want, 0.1 * want) << times[i];
  }
}

TEST(ImuModel, DevicesCarryTheirDatasheetFigures) {
  const ts::ImuModel p = ts::phidget1044ImuModel();
  EXPECT_NEAR(p.gyro.white_sigma, 0.095 * M_PI / 180, 1e-9);
  EXPECT_NEAR(p.gyro.bias_instability, 0.0042 * M_PI / 180, 1e-12);
  EXPECT_NEAR(p.accel.white_sigma, 280e-6 * 9.80665, 1e-9);
  EXPECT_GT(ts::um7ImuModel().gyro.white_sigma, 0.0);
}

TEST(UltrasonicModel, AngledSurfacesGiveNoEchoOrALaterOne) {
  ts::UltrasonicModel m;
  m.max_incidence_rad = 0.3;
  EXPECT_DOUBLE_EQ(ts::nearestEcho({{1.0, 0.5}, {1.4, 0.1}}, m), 1.4);  // the nearer surface is too oblique
  EXPECT_TRUE(std::isinf(ts::nearestEcho({{1.0, 0.5}, {1.2, 0.4}}, m)));
  EXPECT_DOUBLE_EQ(ts::nearestEcho({{1.0, 0.2}, {0.9, 0.6}, {-1.0, 0.0}}, m), 1.0);
}

TEST(UltrasonicModel, TiltedSensorOverTheFloorLosesItsEcho) {
  // Looking down at the floor from 0.35 m: tilted beyond the limit plus half the cone, the datasheet sensor hears
  // nothing while the ideal one still ranges the floor.
  ts::test::StaticWorld w(ts::makeFlatWorld());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::UltrasonicSpec spec;
  spec.noise_m = 0.0;
  std::mt19937 rng(8);
  auto tilted = [](double tilt) {
    ts::SensorPose p;
    p.origin = Eigen::Vector3d(0, 0, 0.35);
    const Eigen::Vector3d x(std::sin(tilt), 0, -std::cos(tilt));
    p.rotation.col(0) = x;
    p.rotation.col(1) = Eigen::Vector3d::UnitY();
    p.rotation.col(2) = x.cross(Eigen::Vector3d::UnitY());
    return p;
  };
  for (double tilt : {0.0, 0.6}) {
    spec.realism = ts::Realism::kIdeal;
    const double ideal = ts::simulateUltrasonic(caster, tilted(tilt), spec, rng);
    spec.realism = ts::Realism::kDatasheet;
    const double datasheet = ts::simulateUltrasonic(caster, tilted(tilt), spec, rng);
    EXPECT_TRUE(std::isfinite(ideal)) << tilt;
    if (tilt - 0.5 * spec.fov_rad > spec.model.max_incidence_rad) {
      EXPECT_TRUE(std::isinf(datasheet)) << tilt;
    } else {
      EXPECT_NEAR(datasheet, ideal, 1e-9) << tilt;
    }
  }
}

TEST(UltrasonicModel, CrossTalkAtItsRate) {
  std::mt19937 rng(9);
  int heard = 0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) heard += ts::crossTalk(1.5, 2.0, 0.2, rng) == 1.0;
  EXPECT_NEAR(heard / double(n), 0.2, 0.012);
  EXPECT_DOUBLE_EQ(ts::crossTalk(0.8, 2.0, 1.0, rng), 0.8);  // its own echo comes first
  EXPECT_DOUBLE_EQ(ts::crossTalk(1.5, 2.0, 0.0, rng), 1.5);
}
