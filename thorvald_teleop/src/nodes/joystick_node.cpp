// Node `joystick`: reads a Linux joystick device and publishes sensor_msgs/Joy, with the joy package's parameters
// `dev`, `deadzone`, `autorepeat_rate` and `coalesce_interval` (see README.md).
#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <thorvald_common/ros/param_reader.h>
#include <sensor_msgs/Joy.h>

#include "thorvald_common/stop_signals.h"
#include "thorvald_teleop/joystick_device.h"
#include "thorvald_teleop/joystick_state.h"

namespace thorvald_teleop {
namespace {

struct JoystickParams {
  std::string dev = "/dev/input/js0";
  double deadzone = 0.05;              ///< fraction of full scale reading 0
  double autorepeat_rate_hz = 0.0;     ///< [Hz] republish the state while nothing changes; 0 = only on change
  double coalesce_interval_s = 0.001;  ///< [s] events closer than this are published together
  double retry_interval_s = 1.0;       ///< [s] between attempts to open a missing device
};

JoystickParams loadParams(ros::NodeHandle& pnh) {
  using thorvald_common::ParamRange;
  thorvald_common::ParamReader params(pnh);
  JoystickParams p;
  p.dev = params.text("dev", p.dev);
  p.deadzone = params.number("deadzone", p.deadzone, ParamRange{0.0, 1.0, false, true});
  p.autorepeat_rate_hz =
      params.number("autorepeat_rate", p.autorepeat_rate_hz, ParamRange::closed(0.0, 1000.0), "Hz, 0 = off");
  p.coalesce_interval_s =
      params.number("coalesce_interval", p.coalesce_interval_s, ParamRange{0.0, 1.0, false, true}, "s");
  p.retry_interval_s = params.number("retry_interval", p.retry_interval_s, ParamRange::aboveUpTo(0.0, 60.0), "s");
  if (p.dev.empty()) {
    throw thorvald_common::ParamError(params.node() +
                                      ": parameter ~dev: found an empty string, expected a device path such as "
                                      "/dev/input/js0");
  }
  params.alsoRead("diagnostic_period");  // diagnostic_updater's
  params.finish();
  return p;
}

/// Owns the device and the loop: open (retrying while missing), read events, publish on change (coalesced) and at
/// the autorepeat rate. Runs on the main thread; diagnostics are published from the same loop.
class JoystickNode {
 public:
  JoystickNode(ros::NodeHandle nh, ros::NodeHandle pnh)
      : pnh_(pnh), params_(loadParams(pnh_)), state_(params_.deadzone), updater_(nh, pnh) {
    pub_ = nh.advertise<sensor_msgs::Joy>("joy", 10);
    updater_.setHardwareID(params_.dev);
    updater_.add("joystick", this, &JoystickNode::diagnose);
  }

  void run() {
    while (ros::ok()) {
      if (!device_.isOpen() && !tryOpen()) {
        waitForRetry();
        continue;
      }
      if (!readOnce()) waitForRetry();  // after a disconnection: no tight reopen loop (e.g. a regular file)
      updater_.update();
      ros::spinOnce();
    }
  }

 private:
  bool tryOpen() {
    std::string error;
    if (!device_.open(params_.dev, error)) {
      char retry[64];
      std::snprintf(retry, sizeof(retry), "; retrying every %.2f s", params_.retry_interval_s);
      status_ = error + retry;
      ROS_ERROR_THROTTLE(10.0, "joystick: %s", status_.c_str());
      return false;
    }
    state_.reset(device_.axisCount(), device_.buttonCount());
    ++connections_;
    status_ = "opened " + params_.dev + (device_.name().empty() ? "" : " (" + device_.name() + ")");
    ROS_INFO("joystick: %s", status_.c_str());
    dirty_ = false;
    return true;
  }

  void waitForRetry() {
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(params_.retry_interval_s);
    while (ros::ok() && ros::WallTime::now() < until) {
      updater_.update();
      ros::spinOnce();
      ros::WallDuration(0.05).sleep();  // device polling interval
    }
  }

  /// Reads and publishes what is due; returns false when the device went away.
  bool readOnce() {
    // Wake up for the autorepeat deadline, the coalescing deadline, or at least every 50 ms for diagnostics.
    double wait_s = 0.05;
    const ros::WallTime now = ros::WallTime::now();
    if (dirty_) wait_s = std::min(wait_s, std::max(0.0, (first_change_ + coalesce()).toSec() - now.toSec()));
    if (params_.autorepeat_rate_hz > 0.0 && published_once_) {
      wait_s = std::min(wait_s, std::max(0.0, (last_publish_ + repeat()).toSec() - now.toSec()));
    }
    std::vector<JsEvent> events;
    std::string error;
    const auto result = device_.read(static_cast<int>(std::ceil(wait_s * 1000.0)), events, error);
    for (const JsEvent& e : events) {
      if (state_.apply(e) && !dirty_) {
        dirty_ = true;
        first_change_ = ros::WallTime::now();
      }
    }
    events_ += events.size();
    if (result == JoystickDevice::ReadResult::kDisconnected) {
      device_.close();
      ++disconnections_;
      status_ = params_.dev + " disconnected: " + error + "; retrying";
      ROS_ERROR_THROTTLE(10.0, "joystick: %s", status_.c_str());
      if (dirty_) publish();
      return false;
    }
    const ros::WallTime after = ros::WallTime::now();
    if (dirty_ && (after - first_change_ >= coalesce() || result == JoystickDevice::ReadResult::kTimeout)) {
      publish();
    } else if (!dirty_ && params_.autorepeat_rate_hz > 0.0 && published_once_ && after - last_publish_ >= repeat()) {
      publish();
    }
    return true;
  }

  ros::WallDuration coalesce() const { return ros::WallDuration(params_.coalesce_interval_s); }
  ros::WallDuration repeat() const { return ros::WallDuration(1.0 / params_.autorepeat_rate_hz); }

  void publish() {
    sensor_msgs::Joy msg;
    msg.header.stamp = ros::Time::now();
    msg.header.frame_id = params_.dev;
    msg.axes = state_.axes();
    msg.buttons = state_.buttons();
    pub_.publish(msg);
    ++published_;
    dirty_ = false;
    published_once_ = true;
    last_publish_ = ros::WallTime::now();
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& s) {
    s.summary(device_.isOpen() ? diagnostic_msgs::DiagnosticStatus::OK : diagnostic_msgs::DiagnosticStatus::ERROR,
              status_);
    s.add("device", params_.dev);
    s.add("connections", connections_);
    s.add("disconnections", disconnections_);
    s.add("events", events_);
    s.add("unknown events", state_.unknownEvents());
    s.add("messages published", published_);
    s.add("axes", state_.axes().size());
    s.add("buttons", state_.buttons().size());
  }

  ros::NodeHandle pnh_;
  JoystickParams params_;
  JoystickDevice device_;
  JoystickState state_;
  ros::Publisher pub_;
  diagnostic_updater::Updater updater_;
  std::string status_ = "starting";
  bool dirty_ = false;
  bool published_once_ = false;
  ros::WallTime first_change_;
  ros::WallTime last_publish_;
  unsigned long connections_ = 0;
  unsigned long disconnections_ = 0;
  unsigned long events_ = 0;
  unsigned long published_ = 0;
};

}  // namespace
}  // namespace thorvald_teleop

int main(int argc, char** argv) {
  ros::init(argc, argv, "joystick", ros::init_options::NoSigintHandler);
  // SIGTERM stops as cleanly as SIGINT, and both within a second in every state; destroyed last.
  thorvald_common::StopSignals stop_signals(ros::requestShutdown, 0.7);
  ros::NodeHandle nh;  // outlives the try block: the last handle's destruction shuts logging down
  ros::NodeHandle pnh("~");
  try {
    thorvald_teleop::JoystickNode node(nh, pnh);
    node.run();
  } catch (const std::exception& e) {
    if (thorvald_common::StopSignals::requested() || !ros::ok()) return 0;  // stopped during start-up
    ROS_FATAL("joystick cannot start: %s", e.what());
    return 1;
  }
  return 0;
}
