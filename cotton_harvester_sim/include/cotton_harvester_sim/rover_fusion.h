#pragma once

// The cotton rover's localisation in process, as the nodes run it (ekf_localization + navsat_transform with
// config/cotton_rover_ekf.yaml's inputs): wheel odometry from the two front encoders and the potentiometer
// (control::ArticulatedOdometry, centre-articulated kinematics) fused as forward speed, vy = 0 and yaw rate; the
// IMUs' yaw (imu0) and yaw rates; each GNSS receiver's fix through thorvald_navigation's NavsatTransform (datum at
// the first fix within datum_max_sigma_m, an RTK fixed one, with imu0's heading), its lever arm removed with the
// filter's heading, x and y fused
// behind a 5-sigma Mahalanobis gate. One filter per sensor set of the paper's Table 1, so the bench can run all
// five on the same drive. ROS-free.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <thorvald_navigation/fusion_ekf.h>
#include <thorvald_navigation/fusion_inputs.h>
#include <thorvald_navigation/fusion_monitor.h>
#include <thorvald_navigation/navsat_transform.h>

#include "cotton_harvester/control/rover_controller.h"
#include "cotton_harvester_sim/rover_sensors.h"

namespace cotton_harvester {
namespace sim {

/// Table 1's five sensor sets, in its order.
enum class SensorSet { kOdometry, kOdometryImu, kOdometryTwoImus, kOdometryTwoImusGnss, kOdometryTwoImusTwoGnss };
constexpr std::array<SensorSet, 5> kTable1Sets = {SensorSet::kOdometry, SensorSet::kOdometryImu,
                                                  SensorSet::kOdometryTwoImus, SensorSet::kOdometryTwoImusGnss,
                                                  SensorSet::kOdometryTwoImusTwoGnss};
/// "Odometry (dead reckoning)", ... as Table 1 names them.
const char* sensorSetName(SensorSet set);
/// The RESULT key's stem: "odom", "odom_imu", "odom_2imu", "odom_2imu_gnss", "odom_2imu_2gnss".
const char* sensorSetKey(SensorSet set);
int gnssReceiversOf(SensorSet set);

struct RoverFusionParams {
  double axle_to_joint_m = 0.91;     ///< the odometry's kinematics (RoverGeometry)
  double metres_per_pulse = 0.0018;  ///< encoder (§2.11)
  /// Wheel odometry's variances, as the rover node publishes them: forward speed [m^2/s^2], yaw rate [rad^2/s^2];
  /// vy = 0 with vy_variance.
  double speed_variance = 0.0025, yaw_rate_variance = 0.01, vy_variance = 0.0025;
  double imu_yaw_variance = 1e-4;   ///< imu0's orientation [rad^2]
  double imu_rate_variance = 1e-6;  ///< gyro z [rad^2/s^2]
  /// Fixes below this state are not fused (an RTK rover's single fix is metres off: it would jerk the estimate
  /// when the fix returns after an outage); they count as no fix for the timeout.
  thorvald_sim::GnssFixState min_fix_state = thorvald_sim::GnssFixState::kFloat;
  /// The datum is taken from the first fix whose horizontal sigma (as fused: a float or single one's scaled, below)
  /// is within this (thorvald_navigation's rule and default, as navsat_transform's ~datum_max_sigma_m): an RTK fixed
  /// epoch's 0.01 m passes, a float one's does not.
  double datum_max_sigma_m = thorvald_navigation::kDatumMaxSigmaM;
  /// x and y process noise [m^2/s] (process_noise_covariance's first two): the position is integrated from the
  /// fused speed and heading, which carry their own noise; robot_localization's default 0.05 made the filter believe
  /// itself 1.2 m off after a 30 s outage that drifted 0.06 m, so the first fix after it was taken whole.
  double position_process_noise = 0.002;
  /// A float or single solution's error wanders slowly (correlated over about 15 s / 60 s, the receiver's figures):
  /// fused every epoch as if independent, 5 Hz of them would pull the estimate onto that one error. Their variance is
  /// scaled by 2 tau / epoch period, the white noise equivalent to the correlated error; fixed epochs are not scaled.
  double float_correlation_s = 15.0, single_correlation_s = 60.0;
  double gnss_period_s = 0.2;           ///< the receiver's epoch period [s]
  double gnss_gate_sigma = 5.0;         ///< odom1_pose_rejection_threshold
  double gnss_timeout_s = 35.0;         ///< ekf_localization's gps_timeout: a tree line's outage is bridged
  double input_timeout_s = 0.5;         ///< any other input
  thorvald_sim::GnssModelParams datum;  ///< only datum_* are read: the GNSS model's local frame, for the fixes
};

/// One sensor set's filter, fed the sensors' readings in time order.
class RoverFusion {
 public:
  /// `antennas_in_base`: each receiver's antenna in base_link [m] (from the robot's description: tf).
  RoverFusion(SensorSet set, const RoverFusionParams& params, const std::vector<Eigen::Vector3d>& antennas_in_base);

  void onImu(const ImuReading& imu);
  void onWheels(const WheelReading& wheels);
  void onGnss(const GnssReading& gnss);

  /// The estimate at `t` [s] (the filter predicted to t when t is later than its last measurement).
  RoverPose2d estimate(double t);
  /// 1-sigma of x and y [m] now.
  Eigen::Vector2d positionSigma() const;
  /// The health as ekf_localization reports it (localization_ok false: stop).
  thorvald_navigation::FusionHealth health(double t) const { return monitor_.evaluate(t); }
  long gnssFused() const { return gnss_fused_; }
  long gnssRefused() const { return gnss_refused_; }
  SensorSet set() const { return set_; }
  bool initialized() const { return ekf_.initialized(); }
  /// Latitude and longitude of a point of the filter's world frame, through the first receiver's datum (nothing
  /// before it is set).
  std::optional<thorvald_navigation::LatLon> toLatLon(double x, double y) const;

 private:
  void fuse(const std::string& input, double t, const std::vector<thorvald_navigation::Measurement>& z);

  SensorSet set_;
  RoverFusionParams p_;
  std::vector<Eigen::Vector3d> antennas_;
  thorvald_navigation::FusionEkf ekf_;
  thorvald_navigation::FusionMonitor monitor_;
  EncoderOdometry wheels_;
  std::optional<double> imu0_yaw_;
  std::vector<thorvald_navigation::NavsatTransform> navsat_;
  long gnss_fused_ = 0, gnss_refused_ = 0;
};

}  // namespace sim
}  // namespace cotton_harvester
