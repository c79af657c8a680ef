// The rover's localisation sensors in MuJoCo (encoders against the wheels' turn and the travel, potentiometer
// against the articulation joint, IMU rates, frames and readings, the GNSS receiver's epochs) and the in-process
// fusion's status (GNSS silence and a position jump stop the rover).
#include <cmath>

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include "cotton_harvester_sim/rover_fusion.h"
#include "cotton_harvester_sim/rover_scene.h"
#include "cotton_harvester_sim/rover_sensors.h"

namespace cotton_harvester {
namespace sim {
namespace {

RoverSimParams flatField(thorvald_sim::Realism realism, double slope_deg = 0.0) {
  RoverSimParams p;
  p.realism = realism;
  p.row.plants = 1;
  p.row.bolls_per_plant = 0;
  p.row.first_plant_x_m = 150.0;
  p.row.slope_deg = slope_deg;
  p.camera_width = 64;
  p.camera_height = 48;
  return p;
}

/// Advances the simulation by `seconds`, polling the sensors every step; collects what came.
RoverSensorFrame run(RoverSim& sim, RoverSensors& sensors, double seconds) {
  RoverSensorFrame all;
  const long steps = std::lround(seconds / sim.params().timestep_s);
  for (long i = 0; i < steps; ++i) {
    sim.advance(sim.params().timestep_s);
    RoverSensorFrame f = sensors.poll();
    all.imu.insert(all.imu.end(), f.imu.begin(), f.imu.end());
    if (f.wheels) all.wheels = f.wheels;
    all.gnss.insert(all.gnss.end(), f.gnss.begin(), f.gnss.end());
  }
  return all;
}

double wheelTravel(const RoverSim& sim, int wheel, double start_angle) {
  const mjModel* m = sim.model();
  const int j = mj_name2id(m, mjOBJ_JOINT, kRoverWheelNames[wheel]);
  return (sim.data()->qpos[m->jnt_qposadr[j]] - start_angle) * sim.params().geometry.wheel_radius_m;
}

double wheelAngle(const RoverSim& sim, int wheel) {
  const mjModel* m = sim.model();
  return sim.data()->qpos[m->jnt_qposadr[mj_name2id(m, mjOBJ_JOINT, kRoverWheelNames[wheel])]];
}

TEST(RoverSensors, EncodersCountTheFrontWheelsTravel) {
  RoverSim sim(flatField(thorvald_sim::Realism::kIdeal));
  RoverSensors sensors(sim, RoverSensorParams());
  const double start[2] = {wheelAngle(sim, 0), wheelAngle(sim, 1)};
  const RoverPose2d p0 = sensors.truthPose();
  sim.setSwashplatePwm(115.0);
  const RoverSensorFrame f = run(sim, sensors, 6.0);
  ASSERT_TRUE(f.wheels.has_value());
  const double per_pulse = sim.params().drive.metres_per_pulse;
  // Each count is the wheel's own turn in whole pulses (truncated), read at the reading's time (<= 20 ms earlier).
  for (int w = 0; w < 2; ++w) {
    const double travel = wheelTravel(sim, w, start[w]);
    const std::int32_t pulses = w == 0 ? f.wheels->left_pulses : f.wheels->right_pulses;
    EXPECT_GT(pulses, 500);                                           // the swashplate slews out of the deadband first
    EXPECT_NEAR(pulses * per_pulse, travel, 0.02 * 0.5 + per_pulse);  // 20 ms at <= 0.5 m/s
  }
  // Driving straight: both wheels agree with base_link's true travel within 2 % (contact slip).
  const RoverPose2d p1 = sensors.truthPose();
  const double truth = std::hypot(p1.x - p0.x, p1.y - p0.y);
  const double counted = 0.5 * (f.wheels->left_pulses + f.wheels->right_pulses) * per_pulse;
  EXPECT_NEAR(counted, truth, 0.02 * truth + 0.02);
}

TEST(EncoderOdometry, MeanOfTheFrontEncodersThroughTheArticulatedKinematics) {
  EncoderOdometry e(0.91, 0.002);
  WheelReading w;
  w.time_s = 1.0;
  EXPECT_FALSE(e.add(w));                                     // the first reading only starts it
  w.time_s = 2.0, w.left_pulses = 240, w.right_pulses = 260;  // 250 pulses of 2 mm in 1 s, straight
  EXPECT_TRUE(e.add(w));
  EXPECT_NEAR(e.odometry().speed(), 0.5, 1e-9);
  EXPECT_NEAR(e.odometry().x(), 0.5, 1e-9);
  EXPECT_NEAR(e.odometry().yawRate(), 0.0, 1e-12);
  w.left_pulses = 500;  // no time passed: the latest reading, no step
  EXPECT_FALSE(e.add(w));
  EXPECT_NEAR(e.odometry().x(), 0.5, 1e-9);
  w.time_s = 3.0, w.left_pulses = 500 + 240, w.right_pulses = 260 + 260, w.articulation_deg = 10.0;
  EXPECT_TRUE(e.add(w));  // counted from the reading before
  EXPECT_NEAR(e.odometry().speed(), 0.5, 1e-9);
  EXPECT_GT(std::abs(e.odometry().yawRate()), 0.05);  // articulated: turning
}

TEST(RoverSensors, PotentiometerReadsTheArticulationAndTheOuterWheelTravelsFurther) {
  RoverSim sim(flatField(thorvald_sim::Realism::kDatasheet));
  RoverSensorParams params;
  RoverSensors sensors(sim, params);
  sim.setArticulationDeg(20.0);
  sim.setSwashplatePwm(115.0);
  const RoverSensorFrame f = run(sim, sensors, 8.0);
  ASSERT_TRUE(f.wheels.has_value());
  // The calibration's counts of the joint's angle, with +-1 count of ADC noise (5 counts per degree).
  const double expected_counts = sensors.params().pot.pot_center_counts + 5.0 * sim.potentiometerDeg();
  EXPECT_NEAR(f.wheels->pot_counts, expected_counts, params.pot_noise_counts + 0.5 + 0.5);
  EXPECT_NEAR(f.wheels->articulation_deg, sim.potentiometerDeg(), 0.4);
  EXPECT_NEAR(f.wheels->articulation_deg, 20.0, 1.5);
  // A left turn: the right (outer) front wheel counts more pulses than the left one.
  EXPECT_GT(f.wheels->right_pulses, f.wheels->left_pulses);
}

TEST(RoverSensors, ImusAt120HzInTheirFramesReadGravityAndTheTurn) {
  const double slope_deg = 2.7668;
  RoverSim sim(flatField(thorvald_sim::Realism::kIdeal, slope_deg));
  RoverSensors sensors(sim, RoverSensorParams());
  // Frames in base_link (front axle middle): 31 / 46 cm back from the front, 95 / 132 cm above the ground.
  const RoverGeometry& g = sim.params().geometry;
  EXPECT_NEAR(sensors.imuInBase(0).x(), g.front_length_m - 0.31 - g.axle_to_joint_m, 1e-9);
  EXPECT_NEAR(sensors.imuInBase(0).z(), 0.95 - g.wheel_radius_m, 1e-9);
  EXPECT_NEAR(sensors.imuInBase(1).x(), g.front_length_m - 0.46 - g.axle_to_joint_m, 1e-9);
  EXPECT_NEAR(sensors.imuInBase(1).z(), 1.32 - g.wheel_radius_m, 1e-9);
  EXPECT_NEAR(sensors.antennaInBase(0).z(), 2.46 - g.wheel_radius_m, 1e-9);
  // At rest on the slope, facing uphill: the specific force is gravity's reaction tilted by the slope.
  RoverSensorFrame f = run(sim, sensors, 2.0);
  int count[2] = {0, 0};
  for (const ImuReading& r : f.imu) ++count[r.index];
  EXPECT_NEAR(count[0], 240, 2);
  EXPECT_EQ(count[0], count[1]);
  const double th = slope_deg * M_PI / 180.0, gravity = 9.80665;
  const ImuReading& rest = f.imu.back();
  EXPECT_NEAR(rest.accel_mps2.x(), gravity * std::sin(th), 0.05);
  EXPECT_NEAR(rest.accel_mps2.y(), 0.0, 0.05);
  EXPECT_NEAR(rest.accel_mps2.z(), gravity * std::cos(th), 0.05);
  EXPECT_NEAR(rest.gyro_radps.norm(), 0.0, 1e-3);
  // Turning: the gyro's z follows the true heading's rate; the orientation follows the heading.
  sim.setArticulationDeg(30.0);
  sim.setSwashplatePwm(115.0);
  run(sim, sensors, 4.0);
  const RoverPose2d a = sensors.truthPose();
  f = run(sim, sensors, 2.0);
  const RoverPose2d b = sensors.truthPose();
  double rate = 0.0;
  int n = 0;
  for (const ImuReading& r : f.imu)
    if (r.index == 0) rate += r.gyro_radps.z(), ++n;
  const double truth_rate = std::remainder(b.yaw - a.yaw, 2.0 * M_PI) / 2.0;
  EXPECT_GT(truth_rate, 0.05);
  EXPECT_NEAR(rate / n, truth_rate, 0.05 * truth_rate);
  const Eigen::Matrix3d r = f.imu.back().orientation.toRotationMatrix();
  EXPECT_NEAR(std::remainder(std::atan2(r(1, 0), r(0, 0)) - b.yaw, 2.0 * M_PI), 0.0, 0.01);
}

TEST(RoverSensors, GnssAt5HzSpeaksNmeaAtTheAntenna) {
  RoverSim sim(flatField(thorvald_sim::Realism::kIdeal));
  RoverSensors sensors(sim, RoverSensorParams());
  const RoverSensorFrame f = run(sim, sensors, 2.0);
  ASSERT_NEAR(static_cast<double>(f.gnss.size()), 10.0, 1.0);
  const GnssReading& g = f.gnss.back();
  EXPECT_EQ(g.solution.state, thorvald_sim::GnssFixState::kFixed);
  ASSERT_EQ(g.sentences.size(), 3u);
  EXPECT_EQ(g.sentences[0].rfind("$GNGGA,", 0), 0u);
  const Eigen::Vector3d antenna = sensors.worldPointOfBase(sensors.antennaInBase(0));
  EXPECT_NEAR((g.solution.enu_m - antenna).norm(), 0.0, 0.01);
}

/// A GNSS epoch at a local east-north position around the default datum.
GnssReading fixAt(double t, double east, double north) {
  thorvald_sim::GnssModelParams p;
  const thorvald_sim::GeodeticDatum datum{p.datum_latitude_deg, p.datum_longitude_deg, p.datum_altitude_m};
  GnssReading g;
  g.solution.time_s = t;
  g.solution.state = thorvald_sim::GnssFixState::kFixed;
  const Eigen::Vector3d geo = datum.toGeodetic({east, north, 0.0});
  g.solution.latitude_deg = geo.x();
  g.solution.longitude_deg = geo.y();
  g.solution.altitude_m = geo.z();
  g.solution.sigma_m = {0.01, 0.01, 0.02};
  return g;
}

TEST(RoverFusion, GnssSilenceBeyondItsTimeoutOrAJumpStopsTheRover) {
  RoverFusionParams p;
  p.gnss_timeout_s = 5.0;
  RoverFusion fusion(SensorSet::kOdometryTwoImusGnss, p, {Eigen::Vector3d::Zero()});
  double t = 0.0;
  auto feed = [&](double until, bool gnss, double jump) {
    for (; t < until; t += 0.02) {
      WheelReading w;
      w.time_s = t;
      for (int i = 0; i < 2; ++i) {
        ImuReading imu;
        imu.index = i;
        imu.time_s = t;
        fusion.onImu(imu);
      }
      fusion.onWheels(w);
      if (gnss && std::fmod(t + 1e-9, 0.2) < 0.02) fusion.onGnss(fixAt(t, 3.0 + jump, 4.0));
    }
  };
  feed(2.0, true, 0.0);
  EXPECT_TRUE(fusion.health(t).localization_ok) << fusion.health(t).summary();
  const RoverPose2d at_rest = fusion.estimate(t);
  EXPECT_NEAR(at_rest.x, 0.0, 0.01);  // the datum puts the first fix at the filter's pose
  feed(6.0, false, 0.0);              // 4 s of silence: within the timeout
  EXPECT_TRUE(fusion.health(t).localization_ok);
  feed(8.0, false, 0.0);  // 6 s: beyond it
  EXPECT_FALSE(fusion.health(t).localization_ok);
  feed(9.0, true, 0.0);
  EXPECT_TRUE(fusion.health(t).localization_ok);
  feed(9.3, true, 10.0);  // a 10 m jump is refused by the gate
  EXPECT_FALSE(fusion.health(t).localization_ok);
  EXPECT_GT(fusion.gnssRefused(), 0);
  EXPECT_NEAR(fusion.estimate(t).x, 0.0, 0.05);
}

}  // namespace
}  // namespace sim
}  // namespace cotton_harvester
