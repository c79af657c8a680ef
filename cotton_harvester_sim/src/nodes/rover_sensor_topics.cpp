#include "rover_sensor_topics.h"

#include <cmath>

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/String.h>
#include <tf2/LinearMath/Quaternion.h>

#include "cotton_harvester_sim/rover_scene.h"

namespace cotton_harvester {
namespace sim {

namespace {

using thorvald_common::ParamRange;

/// ROS time of a simulated time (1 s after its start, as mujoco_rover_sim's /clock).
ros::Time stampOf(double sim_time_s) { return ros::Time(1.0 + sim_time_s); }

geometry_msgs::Quaternion yawQuaternion(double yaw) {
  tf2::Quaternion q;
  q.setRPY(0.0, 0.0, yaw);
  geometry_msgs::Quaternion out;
  out.x = q.x();
  out.y = q.y();
  out.z = q.z();
  out.w = q.w();
  return out;
}

}  // namespace

SensorTopicsConfig readSensorTopicsConfig(thorvald_common::ParamReader& r, unsigned seed) {
  SensorTopicsConfig c;
  c.publish = r.flag("publish_sensors", c.publish);
  RoverSensorParams& s = c.sensors;
  s.imu_rate_hz = r.number("imu_rate_hz", s.imu_rate_hz, ParamRange::aboveUpTo(0.0, 1000.0), "Hz");
  s.wheel_rate_hz = r.number("wheel_rate_hz", s.wheel_rate_hz, ParamRange::aboveUpTo(0.0, 1000.0), "Hz");
  s.gnss.rate_hz = r.number("gnss_rate_hz", s.gnss.rate_hz, ParamRange::aboveUpTo(0.0, 20.0), "Hz");
  s.seed = seed;
  s.gnss.seed = seed;
  c.base_frame = r.text("base_frame", c.base_frame);
  c.odom_frame = r.text("odom_frame", c.odom_frame);
  c.world_frame = r.text("truth_frame", c.world_frame);
  c.imu_frames[0] = r.text("imu_front_frame", c.imu_frames[0]);
  c.imu_frames[1] = r.text("imu_rear_frame", c.imu_frames[1]);
  c.gps_frame = r.text("gps_frame", c.gps_frame);
  if (const std::string bad = s.check(); !bad.empty()) r.reject("imu_rate_hz/wheel_rate_hz/gnss_rate_hz", bad);
  return c;
}

RoverSensorTopics::RoverSensorTopics(ros::NodeHandle& nh, const RoverSim& sim, const SensorTopicsConfig& config)
    : sim_(sim), config_(config), wheels_(sim.params().geometry.axle_to_joint_m, sim.params().drive.metres_per_pulse) {
  if (!config_.publish) return;
  imu_pub_[0] = nh.advertise<sensor_msgs::Imu>("imu_front/data", 50);
  imu_pub_[1] = nh.advertise<sensor_msgs::Imu>("imu_rear/data", 50);
  joints_pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 20);
  odom_pub_ = nh.advertise<nav_msgs::Odometry>("odometry/wheel", 20);
  nmea_pub_ = nh.advertise<std_msgs::String>("nmea_sentence", 50);
  truth_pub_ = nh.advertise<nav_msgs::Odometry>("sim/truth/base_link", 20);
  publishMounts();
}

void RoverSensorTopics::publishMounts() {
  const RoverSensors mounts(sim_, config_.sensors);  // only for the mounts: samples nothing
  std::vector<geometry_msgs::TransformStamped> tfs;
  const auto add = [&](const std::string& child, const Eigen::Vector3d& p) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = stampOf(sim_.time());
    t.header.frame_id = config_.base_frame;
    t.child_frame_id = child;
    t.transform.translation.x = p.x();
    t.transform.translation.y = p.y();
    t.transform.translation.z = p.z();
    t.transform.rotation.w = 1.0;  // level, x forward: base_link's axes (RoverSensors' mounts)
    tfs.push_back(t);
  };
  add(config_.imu_frames[0], mounts.imuInBase(0));
  add(config_.imu_frames[1], mounts.imuInBase(1));
  add(config_.gps_frame, mounts.antennaInBase(0));
  static_tf_.sendTransform(tfs);
}

bool RoverSensorTopics::wanted() {
  if (!config_.publish) return false;
  const bool any = imu_pub_[0].getNumSubscribers() > 0 || imu_pub_[1].getNumSubscribers() > 0 ||
                   joints_pub_.getNumSubscribers() > 0 || odom_pub_.getNumSubscribers() > 0 ||
                   nmea_pub_.getNumSubscribers() > 0 || truth_pub_.getNumSubscribers() > 0;
  if (any && !sensors_) {
    sensors_ = std::make_unique<RoverSensors>(sim_, config_.sensors);
    wheels_ = EncoderOdometry(sim_.params().geometry.axle_to_joint_m, sim_.params().drive.metres_per_pulse);
    ROS_INFO("mujoco_rover_sim: sensors on at %.3f s (IMUs %.0f Hz, encoders %.0f Hz, GNSS %.0f Hz)", sim_.time(),
             config_.sensors.imu_rate_hz, config_.sensors.wheel_rate_hz, config_.sensors.gnss.rate_hz);
  } else if (!any && sensors_) {
    sensors_.reset();
    ROS_INFO("mujoco_rover_sim: sensors off at %.3f s (no subscriber)", sim_.time());
  }
  return any;
}

void RoverSensorTopics::afterStep() {
  if (!sensors_) return;
  const RoverSensorFrame f = sensors_->poll();
  for (const ImuReading& imu : f.imu) publishImu(imu);
  if (f.wheels) {
    publishWheels(*f.wheels);
    publishTruth(f.wheels->time_s);
  }
  for (const GnssReading& g : f.gnss) {
    for (const std::string& sentence : g.sentences) {
      std_msgs::String s;
      s.data = sentence;
      nmea_pub_.publish(s);
    }
  }
}

void RoverSensorTopics::publishImu(const ImuReading& imu) {
  sensor_msgs::Imu m;
  m.header.stamp = stampOf(imu.time_s);
  m.header.frame_id = config_.imu_frames[imu.index];
  m.orientation.x = imu.orientation.x();
  m.orientation.y = imu.orientation.y();
  m.orientation.z = imu.orientation.z();
  m.orientation.w = imu.orientation.w();
  m.angular_velocity.x = imu.gyro_radps.x();
  m.angular_velocity.y = imu.gyro_radps.y();
  m.angular_velocity.z = imu.gyro_radps.z();
  m.linear_acceleration.x = imu.accel_mps2.x();
  m.linear_acceleration.y = imu.accel_mps2.y();
  m.linear_acceleration.z = imu.accel_mps2.z();
  for (int i = 0; i < 3; ++i) {
    m.orientation_covariance[static_cast<size_t>(4 * i)] = config_.imu_orientation_variance;
    m.angular_velocity_covariance[static_cast<size_t>(4 * i)] = config_.imu_rate_variance;
    m.linear_acceleration_covariance[static_cast<size_t>(4 * i)] = config_.imu_accel_variance;
  }
  imu_pub_[imu.index].publish(m);
}

void RoverSensorTopics::publishWheels(const WheelReading& w) {
  const double per_pulse = sim_.params().drive.metres_per_pulse, radius = sim_.params().geometry.wheel_radius_m;
  const ros::Time stamp = stampOf(w.time_s);
  sensor_msgs::JointState joints;
  joints.header.stamp = stamp;
  joints.name = {kRoverWheelNames[0], kRoverWheelNames[1], "articulation"};
  joints.position = {w.left_pulses * per_pulse / radius, w.right_pulses * per_pulse / radius,
                     w.articulation_deg * M_PI / 180.0};
  joints_pub_.publish(joints);

  // Wheel odometry as the EKF's odom0 takes it (EncoderOdometry), dt in simulated time.
  wheels_.add(w);
  const control::ArticulatedOdometry& odometry = wheels_.odometry();
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = config_.odom_frame;
  odom.child_frame_id = config_.base_frame;
  odom.pose.pose.position.x = odometry.x();
  odom.pose.pose.position.y = odometry.y();
  odom.pose.pose.orientation = yawQuaternion(odometry.yaw());
  odom.pose.covariance[0] = odom.pose.covariance[7] = per_pulse * per_pulse;
  odom.pose.covariance[35] = config_.yaw_rate_variance;
  odom.twist.twist.linear.x = odometry.speed();
  odom.twist.twist.angular.z = odometry.yawRate();
  odom.twist.covariance[0] = config_.speed_variance;
  odom.twist.covariance[7] = config_.vy_variance;
  odom.twist.covariance[35] = config_.yaw_rate_variance;
  odom_pub_.publish(odom);
}

void RoverSensorTopics::publishTruth(double t) {
  if (truth_pub_.getNumSubscribers() == 0) return;
  const RoverPose2d p = sensors_->truthPose();
  nav_msgs::Odometry truth;
  truth.header.stamp = stampOf(t);
  truth.header.frame_id = config_.world_frame;
  truth.child_frame_id = config_.base_frame;
  truth.pose.pose.position.x = p.x;
  truth.pose.pose.position.y = p.y;
  truth.pose.pose.orientation = yawQuaternion(p.yaw);
  truth_pub_.publish(truth);
}

}  // namespace sim
}  // namespace cotton_harvester
