#include "base_driver_ros.h"

#include <sensor_msgs/BatteryState.h>
#include <tf2/LinearMath/Quaternion.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "thorvald_common/ros/param_reader.h"
#include "thorvald_base/ros/base_calculator_loader.h"
#include "thorvald_base/ros/robot_config_params.h"
#include "thorvald_base/simulated_drive.h"

namespace thorvald_base {
namespace {

boost::array<double, 36> covariance6(const Eigen::Matrix3d& c) {
  // (x, y, yaw) of the planar estimate into (x, y, z, roll, pitch, yaw); unobserved axes get a large variance.
  boost::array<double, 36> out{};
  const int idx[3] = {0, 1, 5};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[idx[i] * 6 + idx[j]] = c(i, j);
  for (int k : {2, 3, 4}) out[k * 6 + k] = 1e6;
  return out;
}

/// The `tf_prefix` of the robot's namespace (searched upwards, as tf's convention has it); "" when none is set.
std::string searchedTfPrefix(const ros::NodeHandle& nh) {
  std::string key;
  XmlRpc::XmlRpcValue value;
  if (!nh.searchParam("tf_prefix", key) || !nh.getParam(key, value)) return "";
  if (value.getType() != XmlRpc::XmlRpcValue::TypeString) {
    throw ConfigError("base_driver", key, "must be a string (a frame prefix), found " + describeParamValue(value));
  }
  return static_cast<std::string>(value);
}

}  // namespace

/// The node's parameters besides the robot file, read once at start-up.
struct BaseDriverRos::Settings {
  double rate_hz = 50.0;
  BaseDriverOptions options;
  SimulatedDriveOptions sim;
  int sim_seed = 1;
  std::string hardware_plugin, can_type, can_name;
  CanRelayOptions relay;
  RelayIdList relay_ids;
  double io_hold_s = 0.0;  ///< ~io_command_hold: an output's 'on' lasts this long unless repeated; 0: holds [s]
};

BaseDriverRos::BaseDriverRos(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh), diagnostics_(nh, pnh) {
  ParamReader params(pnh_);
  RobotConfig config = robotConfigFromParams(nh_, params.text("robot_file", ""));
  for (const auto& w : config.warnings) ROS_WARN_STREAM(w);
  const Settings settings = readSettings(params, config);
  if (!simple_sim_) loadHardware(params, settings.hardware_plugin);
  params.finish();

  buildDriver(config, settings);
  connect(settings.rate_hz);
  ROS_INFO_STREAM("base_driver: " << driver_->config().drives.size() << " drives, model "
                                  << driver_->calculator().name() << ", odometry "
                                  << settings.options.calculator.estimator << ", "
                                  << (simple_sim_ ? "simulation" : "hardware") << " at " << settings.rate_hz << " Hz");
}

BaseDriverRos::Settings BaseDriverRos::readSettings(ParamReader& params, const RobotConfig& config) {
  Settings s;
  tf_prefix_ = params.text("tf_prefix", "");
  if (tf_prefix_.empty()) tf_prefix_ = searchedTfPrefix(nh_);
  while (!tf_prefix_.empty() && tf_prefix_.front() == '/') tf_prefix_.erase(0, 1);
  simple_sim_ = params.flag("simple_sim", true);
  enable_odom_tf_ = params.flag("enable_odom_tf", true);
  s.relay.max_sent_per_cycle = params.integer("relay_max_frames_per_cycle", 20, 1, 1000);
  s.relay.max_received_per_cycle = params.integer("relay_max_received_per_cycle", 200, 1, 1000);
  s.rate_hz = params.number("rate", 50.0, ParamRange::aboveUpTo(0.0, 1000.0), "Hz");

  BaseDriverOptions& options = s.options;
  options.cmd_vel_timeout_s = params.number("cmd_vel_timeout", 0.5, ParamRange::aboveUpTo(0.0, 60.0), "s");
  options.calculator.estimator =
      params.choice("odometry_estimator", "least_squares", {"least_squares", "random_pairs"});
  options.calculator.seed = static_cast<unsigned>(params.integer("estimator_seed", 1, 0));
  s.sim.speed_noise_radps = params.number("sim_speed_noise", 0.0, ParamRange::closed(0.0, 10.0), "rad/s");
  s.sim.steering_noise_rad = params.number("sim_steering_noise", 0.0, ParamRange::closed(0.0, 0.5), "rad");
  s.sim_seed = params.integer("sim_seed", 1, 0);
  s.hardware_plugin = params.text("hardware_plugin", "thorvald_can_devices/CanBaseHardware");
  s.can_type = params.text("can_interface_type", "socketcan");
  s.can_name = params.text("can_interface_name", "can0");
  readLimitsAndBatteryPolicy(params, options);
  s.relay_ids = readRelayIds(params, config);
  s.io_hold_s = params.number("io_command_hold", 0.0, ParamRange::closed(0.0, 60.0), "s");
  params.alsoRead("diagnostic_period");  // read by diagnostic_updater
  return s;
}

void BaseDriverRos::loadHardware(ParamReader& params, const std::string& plugin) {
  hardware_loader_ =
      std::make_unique<pluginlib::ClassLoader<BaseHardware>>("thorvald_base", "thorvald_base::BaseHardware");
  try {
    hardware_ = hardware_loader_->createSharedInstance(plugin);
  } catch (const pluginlib::PluginlibException& e) {
    throw std::runtime_error("cannot load hardware plugin '" + plugin + "' (~hardware_plugin): " + e.what());
  }
  hardware_->readParameters(params);  // its own parameters, through the same reader
}

void BaseDriverRos::buildDriver(const RobotConfig& config, const Settings& s) {
  calculator_loader_ = std::make_unique<BaseCalculatorLoader>();
  std::unique_ptr<BaseCalculator> calculator = calculator_loader_->create(config);

  std::vector<std::unique_ptr<MotorDrive>> drives;
  std::vector<std::unique_ptr<Battery>> batteries;
  if (simple_sim_) {
    SimulatedDriveOptions sim = s.sim;
    for (const auto& d : config.drives) {
      sim.seed = static_cast<unsigned>(s.sim_seed + d.index);
      drives.push_back(std::make_unique<SimulatedDrive>(d, sim));
    }
  } else {
    hardware_->initialize(config, s.can_type, s.can_name);
    relay_ = std::make_unique<CanRelayRos>(nh_, pnh_, *hardware_, relayAllowList(s.relay_ids, *hardware_), s.relay);
    drives = hardware_->takeDrives();
    batteries = hardware_->takeBatteries();
    auto boards = hardware_->takeIoBoards();
    if (!boards.empty()) io_ = std::make_unique<IoBoardsRos>(nh_, std::move(boards), s.io_hold_s);
  }
  driver_ =
      std::make_unique<BaseDriver>(config, std::move(calculator), std::move(drives), std::move(batteries), s.options);

  for (const auto& d : driver_->config().drives) {
    if (d.steered()) joint_names_.push_back(frame("steering" + std::to_string(d.index)));
    joint_names_.push_back(frame("wheel" + std::to_string(d.index)));
  }
}

void BaseDriverRos::connect(double rate_hz) {
  odom_pub_ = nh_.advertise<nav_msgs::Odometry>("odometry/base_raw", 10);
  joint_pub_ = nh_.advertise<sensor_msgs::JointState>("joint_states", 10);
  state_pub_ = nh_.advertise<BaseState>("base_state", 10);
  for (const auto& b : driver_->batteryDevices()) {
    battery_pubs_.push_back(nh_.advertise<sensor_msgs::BatteryState>("battery/" + b->name(), 1));
  }
  // No Nagle on the command connection: a held-back segment would delay a write-through by up to a delayed ACK.
  cmd_sub_ = nh_.subscribe("twist_mux/cmd_vel", 1, &BaseDriverRos::onCommand, this, ros::TransportHints().tcpNoDelay());
  services_.push_back(pnh_.advertiseService("set_drive_params", &BaseDriverRos::onSetDriveParams, this));
  services_.push_back(pnh_.advertiseService("reset_base_odom", &BaseDriverRos::onResetOdom, this));
  services_.push_back(pnh_.advertiseService("home_steering", &BaseDriverRos::onHomeSteering, this));
  services_.push_back(pnh_.advertiseService("safety_stop", &BaseDriverRos::onSafetyStop, this));
  services_.push_back(pnh_.advertiseService("clear_drive_stop", &BaseDriverRos::onClearDriveStop, this));

  diagnostics_.setHardwareID(simple_sim_ ? "simulated base" : "CAN base");
  diagnostics_.add("base", this, &BaseDriverRos::diagnoseBase);
  diagnostics_.add("drives", this, &BaseDriverRos::diagnoseDrives);
  if (!driver_->batteryDevices().empty()) diagnostics_.add("batteries", this, &BaseDriverRos::diagnoseBatteries);
  if (io_)
    diagnostics_.add("io boards", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { io_->diagnose(stat); });
  period_s_ = 1.0 / rate_hz;
  timer_ = nh_.createTimer(ros::Duration(1.0 / rate_hz), &BaseDriverRos::onTimer, this);
}

std::string BaseDriverRos::frame(const std::string& name) const {
  return tf_prefix_.empty() ? name : tf_prefix_ + "/" + name;
}

void BaseDriverRos::readLimitsAndBatteryPolicy(ParamReader& params, BaseDriverOptions& options) {
  // 0 switches a limit or a battery check off; the upper ends are far beyond any Thorvald and catch typing slips.
  TwistLimits& l = options.limits;
  l.max_linear_mps = params.number("max_linear_speed", 0.0, ParamRange::closed(0.0, 20.0), "m/s");
  l.max_angular_radps = params.number("max_angular_speed", 0.0, ParamRange::closed(0.0, 20.0), "rad/s");
  l.max_linear_mps2 = params.number("max_linear_acceleration", 0.0, ParamRange::closed(0.0, 50.0), "m/s^2");
  l.max_angular_radps2 = params.number("max_angular_acceleration", 0.0, ParamRange::closed(0.0, 100.0), "rad/s^2");
  BatteryPolicy& b = options.battery;
  b.under_voltage_v = params.number("battery_under_voltage", b.under_voltage_v, ParamRange::closed(0.0, 100.0), "V");
  b.over_temperature_c =
      params.number("battery_over_temperature", b.over_temperature_c, ParamRange::closed(0.0, 150.0), "degC");
  b.lost_timeout_s = params.number("battery_lost_timeout", b.lost_timeout_s, ParamRange::closed(0.0, 60.0), "s");
  b.slow_linear_mps =
      params.number("battery_slow_linear_speed", b.slow_linear_mps, ParamRange::aboveUpTo(0.0, 20.0), "m/s");
  b.slow_angular_radps =
      params.number("battery_slow_angular_speed", b.slow_angular_radps, ParamRange::aboveUpTo(0.0, 20.0), "rad/s");
  const std::pair<const char*, BatteryAction*> actions[] = {{"battery_under_voltage_action", &b.under_voltage},
                                                            {"battery_over_temperature_action", &b.over_temperature},
                                                            {"battery_lost_action", &b.lost}};
  for (const auto& a : actions) {
    parseBatteryAction(params.choice(a.first, toString(*a.second), {"warn", "slow", "stop"}), a.second);
  }
}

void BaseDriverRos::onCommand(const ros::MessageEvent<const geometry_msgs::Twist>& event) {
  const geometry_msgs::Twist& msg = *event.getConstMessage();
  const Twist2D cmd{msg.linear.x, msg.linear.y, msg.angular.z};
  const ros::Time stamp = ros::Time::now();
  const double now = stamp.toSec();
  // Time the command waited in the callback queue (e.g. behind a control cycle) before it is written through.
  cmd_wait_max_window_s_ = std::max(cmd_wait_max_window_s_, (stamp - event.getReceiptTime()).toSec());
  if (!driver_->setCommand(cmd, now)) {
    ROS_WARN_THROTTLE(1.0, "base_driver: rejected a non-finite command (%lu so far); the base keeps the last valid one",
                      driver_->rejectedCommands());
    return;
  }
  // Written through at once (same limits and stop checks as a cycle); the periodic cycle refreshes it.
  if (driver_->writeThrough(now)) ++write_throughs_;
}

void BaseDriverRos::onTimer(const ros::TimerEvent&) {
  const ros::Time now = ros::Time::now();
  // Real cycle gaps on the wall clock: the rate alone hides a stalled cycle.
  const ros::WallTime wall = ros::WallTime::now();
  if (!last_cycle_wall_.isZero()) {
    const double gap = (wall - last_cycle_wall_).toSec();
    if (gap > 0.0) cycle_rate_hz_ = cycle_rate_hz_ > 0.0 ? 0.9 * cycle_rate_hz_ + 0.1 / gap : 1.0 / gap;
    gap_max_window_s_ = std::max(gap_max_window_s_, gap);
    gap_max_total_s_ = std::max(gap_max_total_s_, gap);
    if (gap > 1.5 * period_s_) missed_cycles_ += static_cast<unsigned long>(gap / period_s_ - 0.5);
  }
  last_cycle_wall_ = wall;
  last_cycle_ = now;
  const bool was_stopped = driver_->driveStop();
  if (hardware_) hardware_->poll(now.toSec());
  driver_->update(now.toSec());
  if (driver_->driveStop() && !was_stopped) {
    ROS_ERROR_STREAM("base_driver: propulsion stopped: " << driver_->driveStopText()
                                                         << "; call ~clear_drive_stop once the drive is back");
  }
  if (relay_) relay_->cycle();
  if (io_) io_->cycle(now);
  publish(now);
  diagnostics_.update();
  const double work = (ros::WallTime::now() - wall).toSec();
  cycle_work_max_window_s_ = std::max(cycle_work_max_window_s_, work);
}

void BaseDriverRos::publish(const ros::Time& now) {
  publishOdometry(now);
  publishJointsAndState(now);
  publishBatteries(now);
}

void BaseDriverRos::publishOdometry(const ros::Time& now) {
  const auto& odom = driver_->odometry();
  const auto& vel = driver_->velocity();
  nav_msgs::Odometry o;
  o.header.stamp = now;
  o.header.frame_id = frame("odom");
  o.child_frame_id = frame("base_link");
  o.pose.pose.position.x = odom.pose().x;
  o.pose.pose.position.y = odom.pose().y;
  tf2::Quaternion q;
  q.setRPY(0.0, 0.0, odom.pose().yaw);
  o.pose.pose.orientation.x = q.x();
  o.pose.pose.orientation.y = q.y();
  o.pose.pose.orientation.z = q.z();
  o.pose.pose.orientation.w = q.w();
  o.pose.covariance = covariance6(odom.covariance());
  o.twist.twist.linear.x = vel.twist.vx;
  o.twist.twist.linear.y = vel.twist.vy;
  o.twist.twist.angular.z = vel.twist.wz;
  o.twist.covariance = covariance6(vel.covariance);
  odom_pub_.publish(o);
  if (enable_odom_tf_) {
    geometry_msgs::TransformStamped t;
    t.header = o.header;
    t.child_frame_id = o.child_frame_id;
    t.transform.translation.x = o.pose.pose.position.x;
    t.transform.translation.y = o.pose.pose.position.y;
    t.transform.rotation = o.pose.pose.orientation;
    tf_broadcaster_.sendTransform(t);
  }
}

void BaseDriverRos::publishJointsAndState(const ros::Time& now) {
  sensor_msgs::JointState js;
  js.header.stamp = now;
  js.name = joint_names_;
  BaseState state;
  state.header.stamp = now;
  state.mode = simple_sim_ ? "simulation" : "hardware";
  state.base_calculator = driver_->calculator().name();
  state.safety_stop = driver_->safetyStop();
  state.drive_stop = driver_->driveStop();
  state.command_timed_out = driver_->stopReason() == StopReason::kCommandTimeout;
  const auto& drives = driver_->config().drives;
  for (size_t i = 0; i < drives.size(); ++i) {
    const auto& fb = driver_->feedback()[i];
    const auto& st = driver_->driveStatus()[i];
    const auto& cmd = driver_->commands()[i];
    if (drives[i].steered()) {
      js.position.push_back(fb.steering_rad);
      js.velocity.push_back(fb.steering_speed_radps);
    }
    js.position.push_back(fb.wheel_position_rad);
    js.velocity.push_back(fb.wheel_speed_radps);
    DriveState ds;
    ds.index = drives[i].index;
    ds.node = drives[i].node;
    ds.type = static_cast<uint8_t>(drives[i].type);
    ds.wheel_speed_cmd = cmd.wheel_speed_radps;
    ds.wheel_speed = fb.wheel_speed_radps;
    ds.wheel_position = fb.wheel_position_rad;
    ds.linear_speed = fb.wheel_speed_radps * drives[i].r_wheel;
    ds.steering_cmd = cmd.steering_rad;
    ds.steering = fb.steering_rad;
    ds.steering_limit = drives[i].steered() ? drives[i].str_lim : 0.0;
    ds.r_wheel = drives[i].r_wheel;
    ds.online = st.online;
    ds.fault = st.fault;
    ds.status = st.text;
    state.drives.push_back(ds);
  }
  joint_pub_.publish(js);
  state_pub_.publish(state);
}

void BaseDriverRos::publishBatteries(const ros::Time& now) {
  const auto readings = driver_->batteries();
  for (size_t i = 0; i < readings.size() && i < battery_pubs_.size(); ++i) {
    const auto& r = readings[i];
    sensor_msgs::BatteryState b;
    b.header.stamp = now;
    // A silent battery's last values are stale: published as unknown (NaN), never as fresh readings.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    b.voltage = r.online ? r.voltage_v : nan;
    b.current = r.online ? r.current_a : nan;
    b.charge = std::numeric_limits<float>::quiet_NaN();
    b.capacity = std::numeric_limits<float>::quiet_NaN();
    b.design_capacity = std::numeric_limits<float>::quiet_NaN();
    b.percentage = r.online ? r.charge_pct / 100.0 : nan;
    b.power_supply_status = r.current_a > 0.05 ? sensor_msgs::BatteryState::POWER_SUPPLY_STATUS_CHARGING
                                               : sensor_msgs::BatteryState::POWER_SUPPLY_STATUS_DISCHARGING;
    b.power_supply_health = r.alarms ? sensor_msgs::BatteryState::POWER_SUPPLY_HEALTH_UNSPEC_FAILURE
                                     : sensor_msgs::BatteryState::POWER_SUPPLY_HEALTH_GOOD;
    b.power_supply_technology = sensor_msgs::BatteryState::POWER_SUPPLY_TECHNOLOGY_LION;
    b.present = r.present && r.online;
    b.location = driver_->batteryDevices()[i]->name();
    for (double t : r.temperatures_c) b.cell_temperature.push_back(r.online ? t : nan);
    battery_pubs_[i].publish(b);
  }
}

bool BaseDriverRos::onSetDriveParams(SetDriveParams::Request& req, SetDriveParams::Response& res) {
  std::vector<DriveParamChange> changes;
  for (const auto& p : req.params) changes.push_back({p.drive, p.key, p.value});
  res.success = driver_->setDriveParams(changes, &res.message);
  if (res.success) {
    ROS_INFO_STREAM("base_driver: set_drive_params: " << res.message);
  } else {
    ROS_WARN_STREAM("base_driver: set_drive_params refused: " << res.message);
  }
  return true;
}

bool BaseDriverRos::onResetOdom(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  driver_->resetOdometry();
  res.success = true;
  res.message = "odometry reset to the origin";
  return true;
}

bool BaseDriverRos::onHomeSteering(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  res.success = driver_->homeSteering(&res.message);
  return true;
}

bool BaseDriverRos::onSafetyStop(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
  driver_->setSafetyStop(req.data);
  res.success = true;
  res.message = req.data ? "safety stop engaged: propulsion stopped until released" : "safety stop released";
  ROS_WARN_STREAM("base_driver: " << res.message);
  return true;
}

bool BaseDriverRos::onClearDriveStop(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  res.success = driver_->clearDriveStop(&res.message);
  return true;
}

}  // namespace thorvald_base
