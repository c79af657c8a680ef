#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <pluginlib/class_loader.hpp>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include <map>
#include <memory>
#include <set>
#include <string>

#include "thorvald_base/BaseState.h"
#include "thorvald_base/CANFrame.h"
#include "thorvald_base/SetDriveParams.h"
#include "thorvald_base/base_driver.h"
#include "thorvald_base/base_hardware.h"
#include "thorvald_base/relay_allow_list.h"
#include "thorvald_base/ros/base_calculator_loader.h"
#include "can_relay_ros.h"
#include "io_boards_ros.h"
#include "thorvald_common/ros/param_reader.h"

namespace thorvald_base {

using thorvald_common::describeParamValue;
using thorvald_common::ParamRange;
using thorvald_common::ParamReader;

/// The base_driver node: reads the robot file from its namespace, builds a BaseDriver on simulated drives or on
/// a hardware plugin, and connects it to topics, services, tf and diagnostics. Single-threaded (one spinner):
/// callbacks and the control timer never run at once.
class BaseDriverRos {
 public:
  /// Throws ConfigError or std::runtime_error when the node cannot start; main() reports it and exits non-zero.
  BaseDriverRos(ros::NodeHandle nh, ros::NodeHandle pnh);

 private:
  struct Settings;
  /// Reads the node's parameters but the robot file and the hardware plugin's; sets tf_prefix_, simple_sim_ and
  /// enable_odom_tf_.
  Settings readSettings(ParamReader& params, const RobotConfig& config);
  /// Loads the hardware plugin (~hardware_plugin), which reads its own parameters through `params`.
  void loadHardware(ParamReader& params, const std::string& plugin);
  /// The BaseDriver on simulated drives or on the hardware's, and the joint names it publishes.
  void buildDriver(const RobotConfig& config, const Settings& settings);
  /// Publishers, the command subscriber, services, diagnostics and the control timer.
  void connect(double rate_hz);
  void readLimitsAndBatteryPolicy(ParamReader& params, BaseDriverOptions& options);
  /// The relay's allow-list as configured: the robot file's implement_can_ids, or ~relay_allowed_ids when set.
  RelayIdList readRelayIds(ParamReader& params, const RobotConfig& config);
  void onCommand(const ros::MessageEvent<const geometry_msgs::Twist>& event);
  void onTimer(const ros::TimerEvent& event);
  bool onSetDriveParams(SetDriveParams::Request& req, SetDriveParams::Response& res);
  bool onResetOdom(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onHomeSteering(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onSafetyStop(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res);
  bool onClearDriveStop(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  void publish(const ros::Time& now);
  void publishOdometry(const ros::Time& now);        ///< odometry/base_raw and, when enabled, odom -> base_link
  void publishJointsAndState(const ros::Time& now);  ///< joint_states and base_state
  void publishBatteries(const ros::Time& now);       ///< battery/<name>
  void diagnoseBase(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnoseDrives(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnoseBatteries(diagnostic_updater::DiagnosticStatusWrapper& stat);
  std::string frame(const std::string& name) const;

  ros::NodeHandle nh_, pnh_;
  std::string tf_prefix_;
  bool simple_sim_ = true;
  bool enable_odom_tf_ = true;
  std::unique_ptr<BaseCalculatorLoader> calculator_loader_;
  std::unique_ptr<pluginlib::ClassLoader<BaseHardware>> hardware_loader_;
  std::shared_ptr<BaseHardware> hardware_;
  std::unique_ptr<BaseDriver> driver_;
  std::unique_ptr<CanRelayRos> relay_;  ///< in hardware mode: the CAN relay for implements
  std::unique_ptr<IoBoardsRos> io_;     ///< in hardware mode, when the robot file has `io`: the relay boards

  ros::Subscriber cmd_sub_;
  ros::Publisher odom_pub_, joint_pub_, state_pub_;
  std::vector<ros::Publisher> battery_pubs_;
  std::vector<ros::ServiceServer> services_;
  ros::Timer timer_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  diagnostic_updater::Updater diagnostics_;
  std::vector<std::string> joint_names_;
  ros::Time last_cycle_;
  ros::WallTime last_cycle_wall_;
  double period_s_ = 0.02;
  double cycle_rate_hz_ = 0.0;
  double gap_max_window_s_ = 0.0, gap_max_total_s_ = 0.0;
  unsigned long missed_cycles_ = 0, write_throughs_ = 0;
  double cycle_work_max_window_s_ = 0.0;  ///< longest time one control cycle took since the last report [s]
  double cmd_wait_max_window_s_ = 0.0;    ///< longest wait of a command in the callback queue since then [s]
};

}  // namespace thorvald_base
