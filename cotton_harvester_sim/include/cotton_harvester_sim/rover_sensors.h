#pragma once

// The cotton rover's localisation sensors on the simulated rover (paper §2.3, Figure 4): two PhidgetSpatial 1044
// IMUs at 120 Hz on the front half, rotary encoders on both front wheels and the articulation potentiometer, and
// the Emlid Reach RS RTK-GNSS receiver at 5 Hz (thorvald_sim's GnssModel, NMEA through nmea_sentences.h). They read
// the MuJoCo state of a RoverSim and follow its realism: `ideal` reads truth without error (a GNSS that is fixed
// from the start with 1 mm of noise), `datasheet` applies the IMU model's noise and drifting biases, the
// receiver's fix states with their errors and acquisition times, and the potentiometer's ADC noise. ROS-free.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <thorvald_sim/gnss_model.h>
#include <thorvald_sim/imu_model.h>

#include "cotton_harvester/control/articulation_controller.h"
#include "cotton_harvester/control/rover_controller.h"
#include "cotton_harvester_sim/rover_sim.h"

namespace cotton_harvester {
namespace sim {

/// Where the sensors sit (paper §2.3): distance back from the front of the rover and height above the ground [m].
/// All on the front half, on its centre line unless said.
struct RoverSensorMounts {
  double imu0_from_front_m = 0.31, imu0_height_m = 0.95;  ///< first IMU (Figure 4)
  double imu1_from_front_m = 0.46, imu1_height_m = 1.32;  ///< second IMU
  double gnss_from_front_m = 0.30, gnss_height_m = 2.46;  ///< the receiver's integrated antenna
  /// Table 1's second receiver: beside the first, this far to the left [m] (the paper gives no place: assumption).
  double gnss2_left_m = 0.5;
};

struct RoverSensorParams {
  RoverSensorMounts mounts;
  double imu_rate_hz = 120.0;          ///< paper §2.3
  double wheel_rate_hz = 50.0;         ///< encoder and potentiometer readings (the navigation controller's telemetry)
  thorvald_sim::GnssModelParams gnss;  ///< the receiver (its defaults: the Emlid Reach RS at 5 Hz)
  bool second_gnss = false;            ///< Table 1's last sensor set
  control::ArticulationParams pot;     ///< the potentiometer's calibration (counts per degree, centre)
  double pot_noise_counts = 1.0;       ///< datasheet: uniform +- ADC noise [counts]
  unsigned seed = 1;
  /// The sensors' realism when it differs from the simulation's (a field of ideal plants, whose datasheet bodies
  /// would only slow the physics down, driven with datasheet sensors); empty: the simulation's.
  std::optional<thorvald_sim::Realism> realism;
  std::string check() const;  ///< empty when sound
};

/// One IMU sample in the IMU's frame (x forward, y left, z up on the front half): gyro [rad/s], specific force
/// [m/s^2] (gravity included, as an accelerometer reads it) and the orientation its driver reports (the gyro
/// integrated from the true orientation at switch-on; it drifts with the gyro's bias) in the world frame (x east,
/// y north, z up).
struct ImuReading {
  int index = 0;  ///< 0: imu0, 1: imu1
  double time_s = 0.0;
  Eigen::Vector3d gyro_radps = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_mps2 = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

/// The navigation controller's readings: both front encoders [pulses] and the potentiometer [ADC counts, and the
/// angle [deg] its calibration gives].
struct WheelReading {
  double time_s = 0.0;
  std::int32_t left_pulses = 0, right_pulses = 0;
  double pot_counts = 0.0;
  double articulation_deg = 0.0;
};

/// Wheel odometry from the encoder readings (paper §2.3): the two front encoders' mean travel and the potentiometer's
/// angle through the articulated kinematics (control::ArticulatedOdometry), one step per reading in its own time. The
/// one step for every user of the readings (RoverFusion, the simulator's odometry/wheel topic).
class EncoderOdometry {
 public:
  EncoderOdometry(double axle_to_joint_m, double metres_per_pulse)
      : odometry_(axle_to_joint_m), metres_per_pulse_(metres_per_pulse) {}
  /// Takes a reading; true when it stepped the odometry (the first reading only starts it; a reading that does not
  /// advance time becomes the latest without a step).
  bool add(const WheelReading& w);
  const control::ArticulatedOdometry& odometry() const { return odometry_; }

 private:
  control::ArticulatedOdometry odometry_;
  double metres_per_pulse_;
  std::optional<WheelReading> last_;
};

/// One receiver epoch: the solution and the NMEA sentences (GGA, RMC, GST) it sends.
struct GnssReading {
  int receiver = 0;  ///< 0: the rover's receiver, 1: Table 1's second one
  thorvald_sim::GnssSolution solution;
  std::vector<std::string> sentences;
};

/// The readings that came due in one poll().
struct RoverSensorFrame {
  std::vector<ImuReading> imu;
  std::optional<WheelReading> wheels;
  std::vector<GnssReading> gnss;
};

/// The rover's pose as the localisation sees it: base_link is the middle of the front axle with the front half's
/// heading (the point the front encoders' travel moves, control::ArticulatedOdometry's pose), x, y [m] in the
/// world, yaw [rad] from the world x axis (east).
struct RoverPose2d {
  double x = 0.0, y = 0.0, yaw = 0.0;
};

/// The sensors of one simulated rover. Call poll() after every physics step (or at least once per IMU period): it
/// returns the readings that came due since the previous call, sampled at the simulation's time. Not
/// thread-safe; keeps a reference to the simulation.
class RoverSensors {
 public:
  /// Throws std::invalid_argument on bad parameters (check(), the GNSS model's validate()).
  RoverSensors(const RoverSim& sim, const RoverSensorParams& params);

  RoverSensorFrame poll();

  /// The frames' mounts in base_link (x forward, y left, z up) [m]: imu0, imu1, gnss0, gnss1.
  Eigen::Vector3d imuInBase(int index) const;
  Eigen::Vector3d antennaInBase(int receiver) const;
  /// Truth (scoring only): base_link's pose now.
  RoverPose2d truthPose() const;
  /// Truth: a world point [m] of the front half given in base_link.
  Eigen::Vector3d worldPointOfBase(const Eigen::Vector3d& in_base) const;
  /// The GNSS models' local east-north-up frame is the simulation's world frame (x east, y north).
  const thorvald_sim::GnssModel& gnss(int receiver) const { return *gnss_[receiver]; }
  const RoverSensorParams& params() const { return params_; }

 private:
  struct ImuState {
    Eigen::Vector3d in_front = Eigen::Vector3d::Zero();  ///< mount in the front body's frame [m]
    std::unique_ptr<thorvald_sim::ImuErrors> errors;
    std::optional<Eigen::Vector3d> last_velocity;  ///< of the mount point, world [m/s]
    double last_t = 0.0;
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  };

  ImuReading readImu(int index, double t);
  WheelReading readWheels(double t);
  Eigen::Vector3d frontPointWorld(const Eigen::Vector3d& in_front) const;
  Eigen::Matrix3d frontRotation() const;
  /// World velocity [m/s] of a point of the front body given in its frame, and the body's angular velocity.
  Eigen::Vector3d frontPointVelocity(const Eigen::Vector3d& in_front, Eigen::Vector3d* omega_world) const;

  const RoverSim& sim_;
  RoverSensorParams params_;
  bool datasheet_ = false;
  std::mt19937 rng_;
  std::array<ImuState, 2> imus_;
  std::vector<std::unique_ptr<thorvald_sim::GnssModel>> gnss_;
  std::vector<Eigen::Vector3d> antennas_in_front_;
  control::ArticulationController pot_;
  int front_body_ = -1;
  int wheel_qpos_[2] = {-1, -1};
  double wheel_start_[2] = {0.0, 0.0};
  double base_in_front_x_ = 0.0;  ///< the front axle ahead of the articulation joint [m]
  double next_imu_s_ = 0.0, next_wheels_s_ = 0.0;
};

/// The rover's receiver for a realism: `ideal` fixed from the start with 1 mm of error (1 mm in every state),
/// `datasheet` the Emlid Reach RS defaults. Datum and seed are kept from `base`.
thorvald_sim::GnssModelParams roverGnssParams(thorvald_sim::Realism realism,
                                              const thorvald_sim::GnssModelParams& base = {});

}  // namespace sim
}  // namespace cotton_harvester
