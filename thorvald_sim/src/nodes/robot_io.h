#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <functional>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "thorvald_sim/camera_renderer.h"
#include "thorvald_sim/sensor_config.h"
#include "thorvald_sim/simulation.h"

namespace thorvald_sim {

/// The ROS side of one simulated robot, in its namespace: takes the actuator targets (base_driver's `joint_states`
/// from its joint simulator, or with encoders from the physics the SimHardware plugin's `sim/joint_commands`, then
/// answering on `sim/joint_measured`), publishes `ground_truth/odom`, the optional map -> odom transform and its
/// sensors. Called from the simulator's one thread only.
class RobotIo {
 public:
  /// `renderer` gives the simulator's one camera renderer (created on first use).
  RobotIo(ros::NodeHandle nh, Simulation& sim, size_t index, const std::string& tf_prefix,
          std::vector<SensorConfig> sensors, const std::string& world_frame, bool publish_map_tf,
          std::function<CameraRenderer&()> renderer, bool physics_encoders = false);

  /// Publishes what is due at simulated time `now`.
  void publish(const ros::Time& now, double ground_truth_period_s);
  /// Forgets sensor schedules (after a reset).
  void restart();
  void diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) const;
  const std::string& name() const { return name_; }

 private:
  struct Sensor {
    SensorConfig config;
    std::string frame;  ///< frame_id of its messages
    int parent_body = -1;
    Eigen::Matrix3d mount;
    double next_s = 0.0;
    std::mt19937 rng;
    std::unique_ptr<ImuErrors> imu_errors;  ///< datasheet IMU: its drifting biases
    ros::Publisher pub, color_pub, info_pub, color_info_pub;
  };

  void onJointStates(const sensor_msgs::JointState::ConstPtr& msg);
  void onOdometry(const nav_msgs::Odometry::ConstPtr& msg);
  void publishSensor(Sensor& s, const ros::Time& now);
  void publishCamera(Sensor& s, const SensorPose& pose, const ros::Time& now);
  std::string frame(const std::string& link) const { return prefix_.empty() ? link : prefix_ + "/" + link; }

  ros::NodeHandle nh_;
  Simulation& sim_;
  size_t index_;
  std::string name_, prefix_, world_frame_;
  bool publish_map_tf_;
  ros::Subscriber joint_sub_, odom_sub_;
  ros::Publisher truth_pub_, measured_pub_;
  bool physics_encoders_;
  std::vector<std::string> measured_joints_;  ///< physics mode: the joints reported on sim/joint_measured
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  std::vector<Sensor> sensors_;
  std::map<std::string, std::pair<int, bool>> actuators_;  ///< joint -> (actuator, is position)
  std::function<CameraRenderer&()> renderer_;
  RenderedView view_;  ///< reused between frames, as the images
  DepthImage depth_img_;
  ColorImage color_img_;
  double next_truth_s_ = 0.0;
  unsigned long camera_frames_ = 0, camera_errors_ = 0;
  unsigned long joint_msgs_ = 0, rejected_values_ = 0, unknown_joints_ = 0;
};

}  // namespace thorvald_sim
