// surface_monitor: classifies the down-facing ultrasonic range finders into floor, rail and edge, sets the wheel
// radius of base_driver on a floor <-> rail transition (350 mm floor wheels, 240 mm rail wheels) and holds the
// safety lock engaged while a wheel stands at an edge or a range finder is silent.
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <sensor_msgs/Range.h>
#include <std_msgs/Bool.h>
#include <thorvald_base/SetDriveParams.h>
#include <thorvald_common/ros/param_reader.h>
#include <thorvald_common/ros/run_node.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <thread>

#include "greenhouse_rail_nav/SurfaceState.h"
#include "greenhouse_rail_nav/surface_classifier.h"

namespace greenhouse_rail_nav {
namespace {

uint8_t toMsg(Surface s) {
  switch (s) {
    case Surface::kFloor:
      return SurfaceState::FLOOR;
    case Surface::kRail:
      return SurfaceState::RAIL;
    case Surface::kEdge:
      return SurfaceState::EDGE;
    default:
      return SurfaceState::UNKNOWN;
  }
}

class SurfaceMonitor {
 public:
  SurfaceMonitor(ros::NodeHandle& nh, ros::NodeHandle& pnh) : nh_(nh) {
    thorvald_common::ParamReader params(pnh);
    const auto any_positive = thorvald_common::ParamRange::above(0.0);
    SurfaceClassifierParams cp;
    cp.floor_range_m = params.number("floor_range", cp.floor_range_m, any_positive, "m");
    cp.rail_height_m = params.number("rail_height", cp.rail_height_m, any_positive, "m");
    cp.tolerance_m = params.number("tolerance", cp.tolerance_m, any_positive, "m");
    cp.edge_margin_m = params.number("edge_margin", cp.edge_margin_m, any_positive, "m");
    cp.confirm_readings = params.integer("confirm_readings", cp.confirm_readings, 1, 100);
    const std::string problems = cp.validate();
    if (!problems.empty()) throw thorvald_common::ParamError(params.node() + ": " + problems);
    sensors_ = params.texts("sensors", {"front_right", "front_left", "mid_right", "mid_left"}, 1, 16, true);
    front_ =
        indices(params, params.texts("front_sensors", {"front_right", "front_left"}, 0, 16, true), "front_sensors");
    wheels_ = indices(params, params.texts("wheel_sensors", {"mid_right", "mid_left"}, 0, 16, true), "wheel_sensors");
    floor_radius_ = params.number("floor_wheel_radius", 0.175, thorvald_common::ParamRange::aboveUpTo(0.0, 2.0), "m");
    rail_radius_ = params.number("rail_wheel_radius", 0.12, thorvald_common::ParamRange::aboveUpTo(0.0, 2.0), "m");
    set_radius_ = params.flag("set_wheel_radius", true);
    sensor_timeout_s_ = params.number("sensor_timeout", 0.5, thorvald_common::ParamRange::above(0.0), "s");
    const double rate = params.number("publish_rate", 20.0, thorvald_common::ParamRange::aboveUpTo(0.0, 200.0), "Hz");
    const std::string lock_topic = params.text("lock_topic", "safety/lock");
    const std::string topic_prefix = params.text("topic_prefix", "ultrasonic/");
    params.alsoRead("diagnostic_period");
    params.finish();

    tracker_ = std::make_unique<SurfaceTracker>(cp, sensors_.size());
    ranges_.assign(sensors_.size(), std::numeric_limits<float>::quiet_NaN());
    stamps_.assign(sensors_.size(), ros::Time(0));
    for (std::size_t i = 0; i < sensors_.size(); ++i) {
      subs_.push_back(nh.subscribe<sensor_msgs::Range>(
          topic_prefix + sensors_[i], 5, [this, i](const sensor_msgs::RangeConstPtr& m) { onRange(i, *m); }));
    }
    lock_pub_ = nh.advertise<std_msgs::Bool>(lock_topic, 1);
    state_pub_ = nh.advertise<SurfaceState>("surface_monitor/state", 5);
    set_params_ = nh.serviceClient<thorvald_base::SetDriveParams>("base_driver/set_drive_params");
    diagnostics_.setHardwareID("down-facing range finders");
    diagnostics_.add("surface", this, &SurfaceMonitor::diagnose);
    timer_ = nh.createTimer(ros::Duration(1.0 / rate), [this](const ros::TimerEvent&) { publish(); });
    if (set_radius_) radius_thread_ = std::thread([this] { radiusLoop(); });
    ROS_INFO("surface_monitor: %zu range finders, locking '%s' on an edge under a wheel or a silent sensor",
             sensors_.size(), nh.resolveName(lock_topic).c_str());
  }

  ~SurfaceMonitor() {
    {
      std::lock_guard<std::mutex> l(mutex_);
      stopping_ = true;
    }
    radius_cv_.notify_all();
    if (radius_thread_.joinable()) radius_thread_.join();
  }

 private:
  std::vector<std::size_t> indices(thorvald_common::ParamReader& params, const std::vector<std::string>& names,
                                   const std::string& key) const {
    std::vector<std::size_t> out;
    for (const auto& n : names) {
      auto it = std::find(sensors_.begin(), sensors_.end(), n);
      if (it == sensors_.end())
        throw thorvald_common::ParamError(params.node() + ": parameter ~" + key + ": '" + n +
                                          "' is not one of ~sensors");
      out.push_back(static_cast<std::size_t>(it - sensors_.begin()));
    }
    if (out.empty()) throw thorvald_common::ParamError(params.node() + ": parameter ~" + key + " is empty");
    return out;
  }

  void onRange(std::size_t i, const sensor_msgs::Range& m) {
    std::lock_guard<std::mutex> l(mutex_);
    double r = m.range;
    // REP 117: +inf is "nothing within range" (an edge for a down-facing sensor), -inf an object too close.
    if (std::isfinite(r) && (r > m.max_range)) r = std::numeric_limits<double>::infinity();
    if (std::isinf(r) && r < 0.0) r = std::numeric_limits<double>::quiet_NaN();
    ranges_[i] = static_cast<float>(r);
    stamps_[i] = ros::Time::now();
    tracker_->update(i, r);
  }

  void publish() {
    SurfaceState s;
    bool locked = false;
    std::string reason;
    Surface wheels = Surface::kUnknown;
    {
      std::lock_guard<std::mutex> l(mutex_);
      const ros::Time now = ros::Time::now();
      s.header.stamp = now;
      s.sensors = sensors_;
      s.ranges = ranges_;
      for (std::size_t i = 0; i < sensors_.size(); ++i) {
        const bool stale = stamps_[i].isZero() || (now - stamps_[i]).toSec() > sensor_timeout_s_;
        s.surfaces.push_back(stale ? SurfaceState::UNKNOWN : toMsg(tracker_->surface(i)));
        if (stale) {
          locked = true;
          reason += (reason.empty() ? "" : "; ") + sensors_[i] + " silent";
        }
      }
      wheels = tracker_->common(wheels_);
      s.front = toMsg(tracker_->common(front_));
      s.wheels = toMsg(wheels);
      for (std::size_t i : wheels_) {
        if (tracker_->surface(i) == Surface::kEdge) {
          locked = true;
          reason += (reason.empty() ? "" : "; ") + std::string("edge under ") + sensors_[i];
        }
      }
      if (locked && last_state_.reason != reason)
        ROS_WARN_THROTTLE(1.0, "surface_monitor: safety lock: %s", reason.c_str());
      s.locked = locked;
      s.reason = reason;
      s.wheel_radius = applied_radius_;
      // A wheel radius follows the surface the drive wheels stand on.
      if (set_radius_ && (wheels == Surface::kFloor || wheels == Surface::kRail)) {
        const double want = wheels == Surface::kFloor ? floor_radius_ : rail_radius_;
        if (want != wanted_radius_) {
          wanted_radius_ = want;
          radius_cv_.notify_all();
        }
      }
      last_state_ = s;
    }
    std_msgs::Bool lock;
    lock.data = locked;
    lock_pub_.publish(lock);
    state_pub_.publish(s);
    diagnostics_.update();
  }

  // Service calls to base_driver run here, so that a slow or absent base_driver never delays the lock.
  void radiusLoop() {
    std::unique_lock<std::mutex> l(mutex_);
    while (!stopping_) {
      radius_cv_.wait_for(l, std::chrono::milliseconds(500));
      if (stopping_) break;
      const double want = wanted_radius_;
      if (want <= 0.0 || want == applied_radius_) continue;
      l.unlock();
      thorvald_base::SetDriveParams srv;
      thorvald_base::DriveParam p;
      p.drive = -1;
      p.key = "r_wheel";
      p.value = want;
      srv.request.params.push_back(p);
      const bool ok = set_params_.waitForExistence(ros::Duration(0.2)) && set_params_.call(srv) && srv.response.success;
      l.lock();
      if (ok) {
        applied_radius_ = want;
        ROS_INFO("surface_monitor: wheel radius set to %.3f m (%s)", want,
                 want == rail_radius_ ? "rail wheels" : "floor wheels");
      } else {
        ROS_WARN_THROTTLE(
            2.0, "surface_monitor: could not set the wheel radius to %.3f m: %s", want,
            srv.response.message.empty() ? "base_driver/set_drive_params not available" : srv.response.message.c_str());
      }
    }
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    std::lock_guard<std::mutex> l(mutex_);
    if (last_state_.locked)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "safety lock: " + last_state_.reason);
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
    static const char* names[] = {"unknown", "floor", "rail", "edge"};
    for (std::size_t i = 0; i < last_state_.sensors.size(); ++i)
      stat.addf(last_state_.sensors[i], "%s (%.3f m)", names[last_state_.surfaces[i] & 3], last_state_.ranges[i]);
    stat.add("wheels", names[last_state_.wheels & 3]);
    stat.add("wheel radius [m]", applied_radius_);
  }

  ros::NodeHandle nh_;
  std::vector<std::string> sensors_;
  std::vector<std::size_t> front_, wheels_;
  double floor_radius_ = 0.175, rail_radius_ = 0.12, sensor_timeout_s_ = 0.5;
  bool set_radius_ = true;
  std::mutex mutex_;
  std::condition_variable radius_cv_;
  bool stopping_ = false;
  double wanted_radius_ = 0.0, applied_radius_ = 0.0;
  std::unique_ptr<SurfaceTracker> tracker_;
  std::vector<float> ranges_;
  std::vector<ros::Time> stamps_;
  SurfaceState last_state_;
  std::vector<ros::Subscriber> subs_;
  ros::Publisher lock_pub_, state_pub_;
  ros::ServiceClient set_params_;
  ros::Timer timer_;
  diagnostic_updater::Updater diagnostics_;
  std::thread radius_thread_;
};

}  // namespace
}  // namespace greenhouse_rail_nav

int main(int argc, char** argv) {
  thorvald_common::RunNodeOptions options;
  options.spinner_threads = 2;
  return thorvald_common::runNode<greenhouse_rail_nav::SurfaceMonitor>(argc, argv, "surface_monitor", options);
}
