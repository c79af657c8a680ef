#pragma once

// The simulated rover's localisation sensors (RoverSensors) as the robot's drivers publish them, in simulated time:
// the two IMUs (sensor_msgs/Imu), the front encoders and the articulation potentiometer (sensor_msgs/JointState and
// the wheel odometry the EKF's odom0 takes, nav_msgs/Odometry), and the RTK receiver's NMEA (std_msgs/String, one
// sentence a message, for nmea_tcp_feeder -> gpsd -> gpsd_client). The sensors' mounts go to /tf_static. Truth
// (base_link's pose in the world) has its own topic, for scoring only. Nothing is sampled while nobody subscribes.

#include <memory>
#include <optional>
#include <string>

#include <ros/ros.h>
#include <thorvald_common/ros/param_reader.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "cotton_harvester/control/rover_controller.h"
#include "cotton_harvester_sim/rover_sensors.h"

namespace cotton_harvester {
namespace sim {

struct SensorTopicsConfig {
  bool publish = true;        ///< ~publish_sensors
  RoverSensorParams sensors;  ///< rates (~imu_rate_hz, ~wheel_rate_hz, ~gnss_rate_hz) and seed
  std::string base_frame = "base_link", odom_frame = "odom", world_frame = "world";
  std::string imu_frames[2] = {"imu_front_link", "imu_rear_link"};
  std::string gps_frame = "gps_link";
  /// Variances on the messages (the in-process fusion's, RoverFusionParams): forward speed and vy [m^2/s^2], yaw rate
  /// [rad^2/s^2]; the IMUs' orientation [rad^2], rate [rad^2/s^2] and acceleration [m^2/s^4].
  double speed_variance = 0.0025, vy_variance = 0.0025, yaw_rate_variance = 0.01;
  double imu_orientation_variance = 1e-4, imu_rate_variance = 1e-6, imu_accel_variance = 1e-2;
};

/// Reads the sensor parameters (~publish_sensors, rates, frames); the seed is the simulation's.
SensorTopicsConfig readSensorTopicsConfig(thorvald_common::ParamReader& r, unsigned seed);

class RoverSensorTopics {
 public:
  RoverSensorTopics(ros::NodeHandle& nh, const RoverSim& sim, const SensorTopicsConfig& config);

  /// Whether anyone listens to a sensor or the truth (checked once per I/O period). Creates the sensors when the
  /// first subscriber comes (the IMUs' orientation starts from the true one then) and drops them when the last goes.
  bool wanted();
  /// Samples the sensors after a physics step and publishes what came due; stamps are 1 s + simulated time.
  void afterStep();

 private:
  void publishImu(const ImuReading& imu);
  void publishWheels(const WheelReading& wheels);
  void publishTruth(double t);
  void publishMounts();

  const RoverSim& sim_;
  SensorTopicsConfig config_;
  ros::Publisher imu_pub_[2], joints_pub_, odom_pub_, nmea_pub_, truth_pub_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  std::unique_ptr<RoverSensors> sensors_;
  EncoderOdometry wheels_;
};

}  // namespace sim
}  // namespace cotton_harvester
