// uv_interlock: sits between the mission's uv_lights request and the lamps' relay, independent of the mission. The
// relay command is on only while the mission asks for light, the robot is on the rails at treatment speed (from within
// speed_on_tolerance of it, kept until it leaves speed_tolerance: no flicker at the band's edge), nobody is
// detected or present and no safety lock or base stop is engaged, every input fresh. Any input that stops permitting
// switches the relay off in its own callback; a stale input does at the next check (check_rate).
#include <diagnostic_updater/diagnostic_updater.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <thorvald_common/ros/param_reader.h>
#include <thorvald_common/ros/run_node.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "greenhouse_rail_nav/SurfaceState.h"
#include "greenhouse_rail_nav/uv_interlock.h"
#include "thorvald_base/BaseState.h"

namespace greenhouse_rail_nav {
namespace {

using thorvald_common::ParamRange;

class UvInterlockNode {
 public:
  UvInterlockNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) : diagnostics_(nh, pnh) {
    thorvald_common::ParamReader params(pnh);
    treat_speed_mps_ = params.number("treat_speed", 0.5, ParamRange::aboveUpTo(0.0, 2.0), "m/s");
    speed_tolerance_mps_ = params.number("speed_tolerance", 0.1, ParamRange::closed(0.0, 1.0), "m/s");
    // Hysteresis: the speed permits from within speed_on_tolerance, and until it leaves speed_tolerance.
    const double on_tolerance = params.number("speed_on_tolerance", 0.05, ParamRange::closed(0.0, 1.0), "m/s");
    speed_window_ = SpeedWindow(treat_speed_mps_, speed_tolerance_mps_, std::min(on_tolerance, speed_tolerance_mps_));
    const double check_rate = params.number("check_rate", 50.0, ParamRange::aboveUpTo(0.0, 1000.0), "Hz");
    const auto timeout = [&](const std::string& name, double fallback) {
      return params.number(name, fallback, ParamRange::closed(0.0, 60.0), "s");
    };
    // The mission publishes uv_lights latched, on change: by default the request never goes stale.
    const size_t request = interlock_.add({"uv_lights request", timeout("request_timeout", 0.0)});
    const size_t rails = interlock_.add({"on rails", timeout("on_rails_timeout", 0.3)});
    const size_t speed = interlock_.add({"treatment speed", timeout("odometry_timeout", 0.3)});
    const size_t detected = interlock_.add({"people_detected", timeout("people_detected_timeout", 0.5)});
    const size_t present = interlock_.add({"people_present", timeout("people_present_timeout", 0.5)});
    const size_t base = interlock_.add({"base stop", timeout("base_state_timeout", 0.3)});
    const double lock_timeout = timeout("lock_timeout", 0.3);
    const auto locks = params.texts("lock_topics", {"safety/lock", "bumper/lock"}, 0, 16, true);
    params.alsoRead("diagnostic_period");
    params.finish();

    relay_pub_ = nh.advertise<std_msgs::Bool>("uv_relay", 1, true);
    const ros::TransportHints fast = ros::TransportHints().tcpNoDelay();
    subscribeBool(nh, "uv_lights", request, true, "the mission asks for the lamps off", fast);
    subscribeBool(nh, "people_detected", detected, false, "a person is detected", fast);
    subscribeBool(nh, "people_present", present, false, "people present (door switch or override)", fast);
    for (const auto& topic : locks) {
      subscribeBool(nh, topic, interlock_.add({"lock " + topic, lock_timeout}), false, "engaged", fast);
    }
    subs_.push_back(nh.subscribe<SurfaceState>(
        "surface_monitor/state", 5,
        [this, rails](const SurfaceState::ConstPtr& m) {
          const bool ok = m->wheels == SurfaceState::RAIL;
          report(rails, ok, "the drive wheels are not on the rails (surface " + std::to_string(m->wheels) + ")");
        },
        ros::VoidConstPtr(), fast));
    subs_.push_back(nh.subscribe<nav_msgs::Odometry>(
        "odometry/base_raw", 5,
        [this, speed](const nav_msgs::Odometry::ConstPtr& m) {
          const double v = m->twist.twist.linear.x;
          report(speed, speed_window_.update(v),
                 "speed " + std::to_string(v).substr(0, 6) + " m/s, treatment speed " +
                     std::to_string(treat_speed_mps_).substr(0, 4) + " m/s");
        },
        ros::VoidConstPtr(), fast));
    subs_.push_back(nh.subscribe<thorvald_base::BaseState>(
        "base_state", 5,
        [this, base](const thorvald_base::BaseState::ConstPtr& m) {
          report(base, !m->safety_stop && !m->drive_stop, m->safety_stop ? "safety stop engaged" : "drive stop");
        },
        ros::VoidConstPtr(), fast));
    diagnostics_.setHardwareID("UV lamps' relay");
    diagnostics_.add("uv interlock", this, &UvInterlockNode::diagnose);
    timer_ = nh.createTimer(ros::Duration(1.0 / check_rate), [this](const ros::TimerEvent&) { check(true); });
    ROS_INFO("uv_interlock: %zu inputs, relay command on %s", interlock_.size(), nh.resolveName("uv_relay").c_str());
  }

 private:
  /// A Bool input that permits the lamps when its value is `permit_value`.
  void subscribeBool(ros::NodeHandle& nh, const std::string& topic, size_t input, bool permit_value,
                     const std::string& why_not, const ros::TransportHints& hints) {
    subs_.push_back(nh.subscribe<std_msgs::Bool>(
        topic, 5,
        [this, input, permit_value, why_not](const std_msgs::Bool::ConstPtr& m) {
          report(input, m->data == permit_value, why_not);
        },
        ros::VoidConstPtr(), hints));
  }

  void report(size_t input, bool permits, const std::string& why_not) {
    interlock_.update(input, permits, ros::Time::now().toSec(), why_not);
    check(false);
  }

  /// Decides and publishes on a change; `periodic` also republishes the unchanged command (base_driver's
  /// ~io_command_hold needs an 'on' repeated) and updates the diagnostics.
  void check(bool periodic) {
    last_ = interlock_.decide(ros::Time::now().toSec());
    const int on = last_.lamps_on ? 1 : 0;
    if (on != published_ || periodic) {
      if (on != published_) {
        if (on) {
          ROS_INFO("uv_interlock: lamps' relay on");
        } else {
          ROS_WARN("uv_interlock: lamps' relay off: %s", last_.blocking.empty() ? "" : last_.blocking[0].c_str());
        }
      }
      published_ = on;
      std_msgs::Bool msg;
      msg.data = last_.lamps_on;
      relay_pub_.publish(msg);
    }
    if (periodic) diagnostics_.update();
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    using diagnostic_msgs::DiagnosticStatus;
    if (last_.lamps_on) {
      stat.summary(DiagnosticStatus::OK, "lamps permitted");
    } else {
      std::string why;
      for (const auto& b : last_.blocking) why += (why.empty() ? "" : "; ") + b;
      stat.summary(DiagnosticStatus::OK, "lamps kept off: " + why);
    }
    for (size_t i = 0; i < interlock_.size(); ++i) {
      const std::string& name = interlock_.spec(i).name;
      std::string state = "permits";
      for (const auto& b : last_.blocking) {
        if (b.compare(0, name.size() + 1, name + ":") == 0) state = b.substr(name.size() + 2);
      }
      stat.add(name, state);
    }
  }

  UvInterlock interlock_;
  InterlockDecision last_;
  double treat_speed_mps_ = 0.5, speed_tolerance_mps_ = 0.1;
  SpeedWindow speed_window_{0.5, 0.1, 0.05};
  int published_ = -1;
  std::vector<ros::Subscriber> subs_;
  ros::Publisher relay_pub_;
  ros::Timer timer_;
  diagnostic_updater::Updater diagnostics_;
};

}  // namespace
}  // namespace greenhouse_rail_nav

int main(int argc, char** argv) {
  return thorvald_common::runNode<greenhouse_rail_nav::UvInterlockNode>(argc, argv, "uv_interlock");
}
