// rover: the hydrostatic rover's movement controller. Reads encoder and potentiometer telemetry from
// the navigation controller's serial port, runs the position PID (eq. 8 deadband mapping) and the
// articulation P control on every telemetry frame, and sends the servo PWM and relay states back.
// Position targets come from the harvest machine, velocities from cmd_vel (teleop through the mux).
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Float64.h>
#include <tf2/LinearMath/Quaternion.h>

#include "cotton_harvester/control/navigation_protocol.h"
#include "cotton_harvester/control/rover_controller.h"
#include "cotton_harvester/control/serial_port.h"
#include "../ros/calibration_params.h"
#include "../ros/node_params.h"

namespace cotton_harvester {
namespace control {
namespace {

class RoverNode {
 public:
  RoverNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeParams& params)
      : updater_(nh, pnh), controller_(loadRoverParams(params)) {
    port_path_ = readString(params, "port", "/dev/ttyACM0");
    baud_ = readInt(params, "baud", 115200, 1);
    reconnect_period_s_ = readPositive(params, "reconnect_period_s", 1.0);
    cmd_vel_timeout_s_ = readPositive(params, "cmd_vel_timeout_s", 0.5);
    telemetry_timeout_s_ = readPositive(params, "telemetry_timeout_s", 0.5);
    frame_id_ = readString(params, "frame_id", "odom");
    child_frame_id_ = readString(params, "child_frame_id", "base_link");
    odometry_ = ArticulatedOdometry(controller_.params().axle_to_joint_m);

    odom_pub_ = nh.advertise<nav_msgs::Odometry>("wheel_odom", 10);
    position_pub_ = nh.advertise<std_msgs::Float64>("rover/position", 10);
    effort_pub_ = nh.advertise<std_msgs::Float64>("rover/effort", 10);
    at_target_pub_ = nh.advertise<std_msgs::Bool>("rover/at_target", 10);
    target_sub_ = nh.subscribe("rover/position_target", 10, &RoverNode::onTarget, this);
    articulation_sub_ = nh.subscribe("rover/articulation_target", 10, &RoverNode::onArticulation, this);
    cmd_vel_sub_ = nh.subscribe("cmd_vel", 10, &RoverNode::onCmdVel, this);
    updater_.setHardwareID("navigation controller " + port_path_);
    updater_.add("rover", this, &RoverNode::diagnose);
    diag_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
      std::lock_guard<std::mutex> lock(mutex_);
      updater_.update();
    });
    worker_ = std::thread([this] { loop(); });
  }

  ~RoverNode() {
    running_ = false;
    if (worker_.joinable()) worker_.join();
  }

 private:
  void onTarget(const std_msgs::Float64::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!std::isfinite(msg->data)) {
      ++rejected_inputs_;
      return;
    }
    controller_.setPositionTarget(msg->data);
  }

  void onArticulation(const std_msgs::Float64::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!std::isfinite(msg->data)) {
      ++rejected_inputs_;
      return;
    }
    controller_.setArticulationTarget(msg->data);
  }

  void onCmdVel(const geometry_msgs::Twist::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!std::isfinite(msg->linear.x) || !std::isfinite(msg->angular.z)) {
      ++rejected_inputs_;
      return;
    }
    controller_.setVelocity(msg->linear.x, msg->angular.z);
    last_cmd_vel_ = std::chrono::steady_clock::now();
  }

  void loop() {
    std::uint8_t buffer[512];
    auto last_attempt = std::chrono::steady_clock::now() - std::chrono::hours(1);
    while (running_ && ros::ok()) {
      if (!port_.isOpen()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        const auto now = std::chrono::steady_clock::now();
        if (std::chrono::duration<double>(now - last_attempt).count() < reconnect_period_s_) continue;
        last_attempt = now;
        std::lock_guard<std::mutex> lock(mutex_);
        if (port_.open(port_path_, baud_)) {
          ROS_INFO("navigation controller connected on %s", port_path_.c_str());
          ++connections_;
          has_telemetry_ = false;
        } else {
          ROS_WARN_THROTTLE(5.0, "navigation controller: %s", port_.lastError().c_str());
        }
        continue;
      }
      const long n = port_.read(buffer, sizeof(buffer), 20);
      std::lock_guard<std::mutex> lock(mutex_);
      if (n < 0) {
        ROS_ERROR("navigation controller lost: %s", port_.lastError().c_str());
        ++disconnections_;
        continue;
      }
      parser_.push(buffer, static_cast<std::size_t>(n));
      for (const auto& telemetry : parser_.takeTelemetry()) control(telemetry);
    }
  }

  /// One control step on a telemetry frame (called with the mutex held).
  void control(const Telemetry& telemetry) {
    const auto now = std::chrono::steady_clock::now();
    const double dt = has_telemetry_ ? std::chrono::duration<double>(now - last_telemetry_).count() : 0.02;
    const double previous_position = controller_.positionM();
    last_telemetry_ = now;
    if (controller_.velocityMode() && std::chrono::duration<double>(now - last_cmd_vel_).count() > cmd_vel_timeout_s_) {
      controller_.holdPosition();  // teleop went quiet: stop where we are
    }
    const RoverOutput output = controller_.update(telemetry, std::clamp(dt, 0.005, 0.2));
    if (has_telemetry_)
      odometry_.update(controller_.positionM() - previous_position, controller_.articulationDeg(), dt);
    has_telemetry_ = true;
    last_telemetry_flags_ = telemetry;
    last_output_ = output;
    DriveCommand command = output.command();
    command.sequence = sequence_++;
    const auto frame = encodeDriveCommand(command);
    if (!port_.write(frame.data(), frame.size())) {
      ROS_ERROR("navigation controller lost: %s", port_.lastError().c_str());
      ++disconnections_;
      return;
    }
    publish(output);
  }

  void publish(const RoverOutput& output) {
    const ros::Time stamp = ros::Time::now();
    nav_msgs::Odometry odom;
    odom.header.stamp = stamp;
    odom.header.frame_id = frame_id_;
    odom.child_frame_id = child_frame_id_;
    odom.pose.pose.position.x = odometry_.x();
    odom.pose.pose.position.y = odometry_.y();
    tf2::Quaternion q;
    q.setRPY(0.0, 0.0, odometry_.yaw());
    odom.pose.pose.orientation.x = q.x();
    odom.pose.pose.orientation.y = q.y();
    odom.pose.pose.orientation.z = q.z();
    odom.pose.pose.orientation.w = q.w();
    odom.twist.twist.linear.x = odometry_.speed();
    odom.twist.twist.angular.z = odometry_.yawRate();
    const double pulse = controller_.params().metres_per_pulse;
    odom.pose.covariance[0] = odom.pose.covariance[7] = pulse * pulse;  // one pulse of resolution
    odom.pose.covariance[35] = 0.01;
    odom.twist.covariance[0] = 0.0025;
    odom.twist.covariance[35] = 0.01;
    odom_pub_.publish(odom);
    std_msgs::Float64 value;
    value.data = controller_.positionM();
    position_pub_.publish(value);
    value.data = output.effort;
    effort_pub_.publish(value);
    std_msgs::Bool at_target;
    at_target.data = controller_.targetReached();
    at_target_pub_.publish(at_target);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
    const double age = std::chrono::duration<double>(std::chrono::steady_clock::now() - last_telemetry_).count();
    if (!port_.isOpen()) {
      status.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "no serial link: " + port_.lastError());
    } else if (!has_telemetry_ || age > telemetry_timeout_s_) {
      status.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "no telemetry");
    } else if (last_telemetry_flags_.watchdog_stop) {
      status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "controller watchdog stopped the rover");
    } else {
      status.summary(diagnostic_msgs::DiagnosticStatus::OK, "driving");
    }
    status.add("port", port_path_);
    status.add("position_m", controller_.positionM());
    status.add("target_m", controller_.targetM());
    status.add("effort", last_output_.effort);
    status.add("pwm", last_output_.pwm);
    status.add("articulation_deg", controller_.articulationDeg());
    status.add("velocity mode", controller_.velocityMode());
    status.add("connections", connections_);
    status.add("disconnections", disconnections_);
    status.add("bytes rejected", parser_.rejectedBytes());
    status.add("inputs rejected (NaN)", rejected_inputs_);
  }

  std::string port_path_, frame_id_, child_frame_id_;
  int baud_ = 115200;
  double reconnect_period_s_ = 1.0, cmd_vel_timeout_s_ = 0.5, telemetry_timeout_s_ = 0.5;
  std::mutex mutex_;
  diagnostic_updater::Updater updater_;
  RoverController controller_;
  ArticulatedOdometry odometry_;
  SerialPort port_;
  NavigationFrameParser parser_;
  bool has_telemetry_ = false;
  Telemetry last_telemetry_flags_;
  RoverOutput last_output_;
  std::uint8_t sequence_ = 0;
  std::size_t connections_ = 0, disconnections_ = 0, rejected_inputs_ = 0;
  std::chrono::steady_clock::time_point last_telemetry_, last_cmd_vel_;
  std::atomic<bool> running_{true};
  std::thread worker_;
  ros::Publisher odom_pub_, position_pub_, effort_pub_, at_target_pub_;
  ros::Subscriber target_sub_, articulation_sub_, cmd_vel_sub_;
  ros::WallTimer diag_timer_;
};

}  // namespace
}  // namespace control
}  // namespace cotton_harvester

int main(int argc, char** argv) {
  ros::init(argc, argv, "rover");
  ros::NodeHandle nh, pnh("~");
  try {
    thorvald_common::ParamReader reader(pnh);
    reader.alsoRead("diagnostic_period");  // diagnostic_updater's own
    cotton_harvester::control::RoverNode node(nh, pnh, cotton_harvester::control::NodeParams(reader));
    reader.finish();
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("rover cannot start: %s", e.what());
    return 1;
  }
  return 0;
}
