// Node `joy_teleop`: gamepad to velocity command, teleop_twist_joy-compatible, with Thorvald drive modes, speed
// gain, deadman, priority lock and steering homing (see README.md).
#include <atomic>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/Twist.h>
#include <ros/ros.h>
#include <sensor_msgs/Joy.h>
#include <std_msgs/Bool.h>
#include <std_srvs/Trigger.h>

#include "../ros/teleop_params.h"
#include "thorvald_common/stop_signals.h"
#include "thorvald_teleop/joy_teleop.h"

namespace thorvald_teleop {
namespace {

geometry_msgs::Twist toTwist(const VelocityCommand& c) {
  geometry_msgs::Twist t;
  t.linear.x = c.linear_x;
  t.linear.y = c.linear_y;
  t.linear.z = c.linear_z;
  t.angular.x = c.angular_x;
  t.angular.y = c.angular_y;
  t.angular.z = c.angular_z;
  return t;
}

/// The ROS shell: Joy in, Twist and the priority lock out, a deadman timer, the homing service call on a worker
/// thread (so a slow homing never stalls the pad). Joy and timer callbacks share the one spinner thread; only the
/// homing result crosses threads, under `home_mutex_`.
class JoyTeleopNode {
 public:
  /// Reads its parameters through `params` (the caller finishes the reader once the node is built).
  JoyTeleopNode(ros::NodeHandle nh, ros::NodeHandle pnh, thorvald_common::ParamReader& params)
      : nh_(nh),
        pnh_(pnh),
        teleop_(loadTeleopConfig(
            params, [this](const std::string& key, XmlRpc::XmlRpcValue& v) { return pnh_.getParam(key, v); })),
        updater_(nh_, pnh_) {
    const double check_rate_hz =
        params.number("deadman_check_rate", 50.0, thorvald_common::ParamRange::aboveUpTo(0.0, 1000.0), "Hz");
    params.alsoRead("diagnostic_period");  // diagnostic_updater's
    cmd_pub_ = nh_.advertise<geometry_msgs::Twist>("cmd_vel", 1, true);
    priority_pub_ = nh_.advertise<std_msgs::Bool>("teleop_joy/joy_priority", 1, true);
    // Queue of 10, not 1: button presses are edges, so no Joy message may be dropped.
    joy_sub_ = nh_.subscribe("joy", 10, &JoyTeleopNode::onJoy, this, ros::TransportHints().tcpNoDelay());
    timer_ = nh_.createTimer(ros::Duration(1.0 / check_rate_hz), &JoyTeleopNode::onTimer, this);
    updater_.setHardwareID("none");
    updater_.add("teleop", this, &JoyTeleopNode::diagnose);
  }

  ~JoyTeleopNode() {
    if (home_thread_.joinable()) home_thread_.join();
  }

 private:
  void onJoy(const sensor_msgs::Joy::ConstPtr& msg) {
    JoyState joy;
    joy.axes = msg->axes;
    joy.buttons = msg->buttons;
    const TeleopActions actions = teleop_.onJoy(joy, ros::Time::now().toSec());
    if (actions.non_finite_axes) {
      ROS_WARN_THROTTLE(1.0, "joy_teleop: joystick message with a NaN or infinite axis, read as centred (%lu so far)",
                        teleop_.nonFiniteMessages());
    }
    apply(actions);
  }

  void onTimer(const ros::TimerEvent&) {
    const TeleopActions actions = teleop_.onTimer(ros::Time::now().toSec());
    if (actions.command) ROS_WARN("joy_teleop: no joystick message for %.2f s, stopping", timeoutS());
    apply(actions);
    updater_.update();
  }

  double timeoutS() const { return teleop_.config().joy_timeout_s; }

  void apply(const TeleopActions& a) {
    if (a.command) cmd_pub_.publish(toTwist(*a.command));
    if (a.priority) {
      std_msgs::Bool b;
      b.data = *a.priority;
      priority_pub_.publish(b);
      ROS_INFO("joy_teleop: priority over autonomy %s", *a.priority ? "on" : "off");
    }
    if (a.mode_changed) ROS_INFO("joy_teleop: drive mode %s", driveModeName(teleop_.mode()));
    if (a.gain_changed) ROS_INFO("joy_teleop: speed gain %.2f", teleop_.gain());
    if (a.home_steering) requestHoming();
  }

  void requestHoming() {
    if (home_busy_.exchange(true)) {
      ROS_WARN("joy_teleop: steering homing already in progress");
      return;
    }
    if (home_thread_.joinable()) home_thread_.join();
    home_thread_ = std::thread([this] {
      ros::ServiceClient client = nh_.serviceClient<std_srvs::Trigger>("base_driver/home_steering");
      std::string result;
      std_srvs::Trigger srv;
      if (!client.exists()) {
        result = "service " + client.getService() + " is not available (is base_driver running?)";
        ROS_ERROR("joy_teleop: cannot home steering: %s", result.c_str());
      } else if (!client.call(srv)) {
        result = "call to " + client.getService() + " failed";
        ROS_ERROR("joy_teleop: cannot home steering: %s", result.c_str());
      } else if (!srv.response.success) {
        result = "refused: " + srv.response.message;
        ROS_WARN("joy_teleop: steering homing %s", result.c_str());
      } else {
        result = "done: " + srv.response.message;
        ROS_INFO("joy_teleop: steering homing %s", result.c_str());
      }
      {
        std::lock_guard<std::mutex> lock(home_mutex_);
        home_result_ = result;
        ++home_requests_;
      }
      home_busy_ = false;
    });
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& s) {
    const double now_s = ros::Time::now().toSec();
    const double age = teleop_.joyAge(now_s);
    if (age < 0.0) {
      s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no joystick message yet");
    } else if (timeoutS() > 0.0 && age > timeoutS()) {
      s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "joystick silent: deadman stop");
    } else {
      s.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
    }
    s.add("drive mode", driveModeName(teleop_.mode()));
    s.add("speed gain", teleop_.gain());
    s.add("priority lock", teleop_.priority());
    s.add("joy age [s]", age);
    s.add("deadman stops", teleop_.deadmanStops());
    s.add("messages with non-finite axes", teleop_.nonFiniteMessages());
    if (teleop_.nonFiniteMessages() > non_finite_reported_) {
      s.mergeSummary(diagnostic_msgs::DiagnosticStatus::WARN,
                     "joystick sent NaN or infinite axes (read as centred): check the joystick driver");
    }
    non_finite_reported_ = teleop_.nonFiniteMessages();
    std::lock_guard<std::mutex> lock(home_mutex_);
    s.add("steering homing requests", home_requests_);
    s.add("steering homing last result", home_result_);
  }

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  JoyTeleop teleop_;
  ros::Publisher cmd_pub_;
  ros::Publisher priority_pub_;
  ros::Subscriber joy_sub_;
  ros::Timer timer_;
  diagnostic_updater::Updater updater_;
  std::atomic<bool> home_busy_{false};
  std::thread home_thread_;
  std::mutex home_mutex_;
  std::string home_result_;
  unsigned long home_requests_ = 0;
  unsigned long non_finite_reported_ = 0;  ///< count at the last diagnostics report
};

}  // namespace
}  // namespace thorvald_teleop

int main(int argc, char** argv) {
  ros::init(argc, argv, "joy_teleop", ros::init_options::NoSigintHandler);
  // SIGTERM stops as cleanly as SIGINT, and both within a second in every state; destroyed last.
  thorvald_common::StopSignals stop_signals(ros::requestShutdown, 0.7);
  ros::NodeHandle nh;  // outlives the try block: the last handle's destruction shuts logging down
  ros::NodeHandle pnh("~");
  try {
    thorvald_common::ParamReader params(pnh);
    thorvald_teleop::JoyTeleopNode node(nh, pnh, params);
    params.finish();  // warns about unread (misspelt) parameters, logs the effective values
    ros::spin();
  } catch (const std::exception& e) {
    if (thorvald_common::StopSignals::requested() || !ros::ok()) return 0;  // stopped during start-up
    ROS_FATAL("joy_teleop cannot start: %s", e.what());
    return 1;
  }
  return 0;
}
