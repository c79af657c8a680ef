// uv_mission: the greenhouse UV-treatment mission (UvMission) on ROS. It talks to navigation only through the
// move_base action (this workspace's headland navigator or a real move_base), reads the rail detector, the
// surface monitor, odometry, the lidar and the bumper's lock, and drives through nav_vel (the mux).
#include <actionlib/client/simple_action_client.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/Twist.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <ros/topic.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/Bool.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>
#include <tf2/utils.h>
#include <tf2_ros/transform_listener.h>
#include <thorvald_common/ros/param_reader.h>
#include <thorvald_state_machine/ros/status_publisher.h>

#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "greenhouse_rail_nav/RailDetectionStatus.h"
#include "greenhouse_rail_nav/SurfaceState.h"
#include "greenhouse_rail_nav/rail_set_file.h"
#include "greenhouse_rail_nav/uv_mission.h"
#include "greenhouse_rail_nav/uv_mission_files.h"
#include "greenhouse_rail_nav/uv_mission_runner.h"
#include "thorvald_map/ros/conversions.h"
#include "uv_mission_params.h"

namespace greenhouse_rail_nav {
namespace {

using MoveBaseClient = actionlib::SimpleActionClient<move_base_msgs::MoveBaseAction>;

Surface fromMsg(uint8_t s) {
  switch (s) {
    case SurfaceState::FLOOR:
      return Surface::kFloor;
    case SurfaceState::RAIL:
      return Surface::kRail;
    case SurfaceState::EDGE:
      return Surface::kEdge;
    default:
      return Surface::kUnknown;
  }
}

/// MissionIO on ROS topics, the move_base action and tf. Callbacks run on the spinner's threads; the mission
/// thread reads copies under the mutex.
class RosMissionIO : public MissionIO {
 public:
  using Config = MissionIoConfig;

  RosMissionIO(ros::NodeHandle& nh, const Config& c)
      : cfg_(c), rate_(c.rate_hz), tf_listener_(tf_), move_base_(nh, "move_base", true), zones_(nh, c.zones, tf_) {
    // The fused odometry (odom_fusion: wheel speeds and the gyro's yaw rate), not the wheels' alone: a drive wheel
    // that stalls or slips against a pipe turns the wheel odometry's heading by radians in seconds while the robot
    // turns by degrees, and the heading held off the rails is odometry's.
    odom_sub_ = nh.subscribe("odometry/filtered", 5, &RosMissionIO::onOdom, this);
    rail_sub_ = nh.subscribe("rail_detection", 5, &RosMissionIO::onRail, this);
    surface_sub_ = nh.subscribe("surface_monitor/state", 5, &RosMissionIO::onSurface, this);
    scan_sub_ = nh.subscribe("scan", 2, &RosMissionIO::onScan, this);
    bumper_sub_ = nh.subscribe("bumper/lock", 5, &RosMissionIO::onBumper, this);
    // The lamps' confirmed state only when lamps_state is remapped (to the relay's io/<board>/out<k>/state).
    lamps_state_known_ = nh.resolveName("lamps_state") != nh.resolveName("lamps_state", false);
    if (lamps_state_known_) {
      lamps_sub_ = nh.subscribe("lamps_state", 5, &RosMissionIO::onLamps, this);
      ROS_INFO("uv_mission: a metre counts as lit only while %s confirms the lamps on",
               nh.resolveName("lamps_state").c_str());
    } else {
      ROS_WARN("uv_mission: no lamps_state remapped: a metre counts as lit from the mission's own uv_lights request");
    }
    cmd_pub_ = nh.advertise<geometry_msgs::Twist>("nav_vel", 5);
    lights_pub_ = nh.advertise<std_msgs::Bool>("uv_lights", 1, true);
    initialpose_pub_ = nh.advertise<geometry_msgs::PoseWithCovarianceStamped>("initialpose", 1);
    std_msgs::Bool off;
    lights_pub_.publish(off);
    if (cfg_.pause_rail_detection) {
      rail_enable_pub_ = nh.advertise<std_msgs::Bool>("rail_detector/enable", 1, true);
      rail_enable_pub_.publish(off);
    }
  }

  double now() override { return ros::Time::now().toSec(); }
  bool ok() override { return ros::ok(); }
  void waitTick() override { rate_.sleep(); }
  void sendNavGoal(const thorvald_base::Pose2D& p) override {
    if (!move_base_.waitForServer(ros::Duration(5.0))) {
      nav_error_ = "no move_base action server";
      nav_failed_now_ = true;
      return;
    }
    nav_failed_now_ = false;
    move_base_msgs::MoveBaseGoal goal;
    goal.target_pose.header.frame_id = cfg_.map_frame;
    goal.target_pose.header.stamp = ros::Time::now();
    goal.target_pose.pose = thorvald_map::toPose(p);
    move_base_.sendGoal(goal);
  }
  NavState navState(std::string* reason) override {
    if (nav_failed_now_) {
      *reason = nav_error_;
      return NavState::kFailed;
    }
    const auto s = move_base_.getState();
    if (s == actionlib::SimpleClientGoalState::SUCCEEDED) return NavState::kSucceeded;
    if (s == actionlib::SimpleClientGoalState::PENDING || s == actionlib::SimpleClientGoalState::ACTIVE)
      return NavState::kActive;
    *reason = s.toString() + (s.getText().empty() ? "" : ": " + s.getText());
    return NavState::kFailed;
  }
  void cancelNav() override {
    if (move_base_.isServerConnected()) move_base_.cancelAllGoals();
  }
  bool odomPose(thorvald_base::Pose2D* p) override {
    std::lock_guard<std::mutex> l(mutex_);
    if (odom_stamp_.isZero() || (ros::Time::now() - odom_stamp_).toSec() > cfg_.odom_timeout_s) return false;
    *p = odom_;
    return true;
  }
  bool mapPose(thorvald_base::Pose2D* p) override {
    try {
      const auto t = tf_.lookupTransform(cfg_.map_frame, cfg_.base_frame, ros::Time(0), ros::Duration(0.2));
      *p = thorvald_map::fromTransform(t.transform);
      return true;
    } catch (const tf2::TransformException& e) {
      ROS_WARN_THROTTLE(5.0, "uv_mission: no %s -> %s: %s", cfg_.map_frame.c_str(), cfg_.base_frame.c_str(), e.what());
      return false;
    }
  }
  void wantRailDetection(bool on) override {
    if (!cfg_.pause_rail_detection || on == rail_wanted_) return;
    rail_wanted_ = on;
    std_msgs::Bool b;
    b.data = on;
    rail_enable_pub_.publish(b);
  }
  RailObservation railObservation() override {
    std::lock_guard<std::mutex> l(mutex_);
    return rail_;
  }
  SurfaceReading surface() override {
    std::lock_guard<std::mutex> l(mutex_);
    return surface_;
  }
  double forwardRange() override {
    std::lock_guard<std::mutex> l(mutex_);
    return forward_range_;
  }
  bool safetyStopped(std::string* why) override {
    std::lock_guard<std::mutex> l(mutex_);
    if (bumper_locked_) *why = "the front bumper's safety stop is latched (clear it with bumper/reset)";
    return bumper_locked_;
  }
  void commandTwist(double v, double w) override {
    geometry_msgs::Twist t;
    t.linear.x = v;
    t.angular.z = w;
    cmd_pub_.publish(t);
  }
  void setLights(bool on) override {
    if (lights_ == on) return;
    lights_ = on;
    std_msgs::Bool b;
    b.data = on;
    lights_pub_.publish(b);
  }
  void resetLocalisation(const thorvald_base::Pose2D& p) override {
    geometry_msgs::PoseWithCovarianceStamped m;
    m.header.frame_id = cfg_.map_frame;
    m.header.stamp = ros::Time::now();
    m.pose.pose = thorvald_map::toPose(p);
    m.pose.covariance[0] = m.pose.covariance[7] = 0.02 * 0.02;
    m.pose.covariance[35] = 0.02 * 0.02;
    initialpose_pub_.publish(m);
  }
  void log(const std::string& line) override { ROS_INFO("uv_mission: %s", line.c_str()); }
  void setZoneContext(const ZoneContext& ctx) override { zones_.setContext(ctx); }
  ZoneVerdict zone() override {
    ZoneVerdict v = zones_.verdict();
    return v;
  }
  bool lightsInDoubt(std::string* why) override { return zones_.lightsInDoubt(why); }
  bool lampsConfirmed(bool* on) override {
    if (!lamps_state_known_) return false;
    std::lock_guard<std::mutex> l(mutex_);
    *on = lamps_on_;  // off until the relay's state was heard
    return true;
  }

 private:
  void onOdom(const nav_msgs::Odometry& m) {
    std::lock_guard<std::mutex> l(mutex_);
    odom_ = thorvald_map::fromPose(m.pose.pose);
    odom_stamp_ = ros::Time::now();
  }
  void onRail(const RailDetectionStatus& m) {
    std::lock_guard<std::mutex> l(mutex_);
    rail_.stamp_s = m.header.stamp.toSec();
    rail_.robot_in_rail = thorvald_base::Pose2D(m.x, m.y, m.yaw);
    switch (m.status) {
      case RailDetectionStatus::FOUND:
        rail_.status = RailObservation::Status::kFound;
        break;
      case RailDetectionStatus::FOUND_X_UNOBSERVED:
        rail_.status = RailObservation::Status::kXUnobserved;
        break;
      default:
        rail_.status = RailObservation::Status::kNotFound;
        break;
    }
  }
  void onSurface(const SurfaceState& m) {
    std::lock_guard<std::mutex> l(mutex_);
    surface_.front = fromMsg(m.front);
    surface_.wheels = fromMsg(m.wheels);
    surface_.stamp_s = ros::Time::now().toSec();
  }
  void onScan(const sensor_msgs::LaserScan& m) {
    const double r = greenhouse_rail_nav::forwardRange(m.ranges, m.angle_min, m.angle_increment,
                                                       cfg_.scan_half_width_rad, m.range_min, m.range_max);
    std::lock_guard<std::mutex> l(mutex_);
    forward_range_ = r;
  }
  void onBumper(const std_msgs::Bool& m) {
    std::lock_guard<std::mutex> l(mutex_);
    bumper_locked_ = m.data;
  }
  void onLamps(const std_msgs::Bool& m) {
    std::lock_guard<std::mutex> l(mutex_);
    lamps_on_ = m.data;
  }

  Config cfg_;
  ros::Rate rate_;
  std::mutex mutex_;
  thorvald_base::Pose2D odom_;
  ros::Time odom_stamp_;
  RailObservation rail_;
  SurfaceReading surface_;
  double forward_range_ = std::numeric_limits<double>::quiet_NaN();
  bool bumper_locked_ = false, lights_ = false;
  bool lamps_state_known_ = false, lamps_on_ = false;  // lamps_state remapped; its latest value
  bool nav_failed_now_ = false;
  std::string nav_error_;
  tf2_ros::Buffer tf_;
  tf2_ros::TransformListener tf_listener_;
  MoveBaseClient move_base_;
  ZoneWatch zones_;
  ros::Subscriber odom_sub_, rail_sub_, surface_sub_, scan_sub_, bumper_sub_, lamps_sub_;
  ros::Publisher cmd_pub_, lights_pub_, initialpose_pub_, rail_enable_pub_;
  bool rail_wanted_ = false;
};

/// map_analyzer, started together with the mission, writes the rail-set file before it publishes rail_targets
/// (latched): the file is read once that message has come, so a file left by an earlier run is not taken. False
/// (said in a fatal log line) when none came in time or the map has no rail set.
bool waitForRailSets(ros::NodeHandle& nh, double wait_s) {
  ROS_INFO("uv_mission: waiting up to %.0f s for map_analyzer's rail_targets", wait_s);
  const auto good = ros::topic::waitForMessage<geometry_msgs::PoseArray>("rail_targets", nh, ros::Duration(wait_s));
  if (!good) {
    ROS_FATAL("uv_mission: no rail_targets from map_analyzer within %.0f s (wait_for_rail_sets)", wait_s);
    return false;
  }
  if (good->poses.empty()) {
    // No good set: either all are uncertain (the file lists them) or nothing was found (no file is written,
    // and one left by an earlier run must not be read).
    const auto uncertain =
        ros::topic::waitForMessage<geometry_msgs::PoseArray>("rail_targets_uncertain", nh, ros::Duration(5.0));
    if (!uncertain || uncertain->poses.empty()) {
      ROS_FATAL("uv_mission: map_analyzer found no rail sets in the map (see its status)");
      return false;
    }
  }
  return true;
}

/// Runs the mission on ROS until the node shuts down: status and report topics, the ~start and ~stop services.
void runMission(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeSettings& settings,
                const std::vector<MissionTarget>& targets) {
  RosMissionIO io(nh, settings.io);
  UvMission mission(io, settings.mission, targets);
  mission.markDone(loadProgress(settings.progress_file));
  thorvald_state_machine::StatusPublisher status(nh, mission.machine(), "mission/status", 1.0);
  ros::Publisher report_pub = nh.advertise<std_msgs::String>("mission/report", 1, true);
  // Why the mission holds (a person or obstacle in the zone, a safety stop, a relay board in doubt), on change.
  ros::Publisher safety_pub = nh.advertise<std_msgs::String>("mission/safety", 1, true);
  diagnostic_updater::Updater diagnostics(nh, pnh);
  diagnostics.setHardwareID("uv_mission");
  ros::Time hold_since;  // zero while not holding
  diagnostics.add("uv_mission safety", [&](diagnostic_updater::DiagnosticStatusWrapper& stat) {
    const std::string why = mission.holdReason();
    if (why.empty()) {
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "not holding");
      return;
    }
    // A long hold is an error for the operator: a person who stays, or something no one moves (check the zone).
    const double held_s = hold_since.isZero() ? 0.0 : (ros::Time::now() - hold_since).toSec();
    stat.summary(held_s > 60.0 ? diagnostic_msgs::DiagnosticStatus::ERROR : diagnostic_msgs::DiagnosticStatus::WARN,
                 "holding: " + why);
    stat.add("holding for [s]", std::round(held_s));
  });
  std::string last_hold = "-";
  ros::Timer safety_timer = nh.createTimer(ros::Duration(0.1), [&](const ros::TimerEvent&) {
    const std::string why = mission.holdReason();
    if (why.empty() != last_hold.empty() || last_hold == "-") hold_since = why.empty() ? ros::Time() : ros::Time::now();
    if (why != last_hold) {
      std_msgs::String m;
      m.data = why.empty() ? "clear" : "holding: " + why;
      safety_pub.publish(m);
      last_hold = why;
      diagnostics.force_update();
    }
    diagnostics.update();
  });
  UvMissionRunner::Hooks hooks;
  hooks.error = [](const std::string& e) { ROS_ERROR("uv_mission: the mission stopped on an error: %s", e.c_str()); };
  hooks.finished = [&](const std::string& outcome) {
    saveProgress(settings.progress_file, mission.done());
    std_msgs::String r;
    r.data = reportCsv(mission.reports());
    report_pub.publish(r);
    if (!mission.stopReason().empty())
      ROS_ERROR("uv_mission: stopped before the end, the robot needs a person: %s", mission.stopReason().c_str());
    // The report covers this run; done() also holds the sets treated by earlier runs.
    ROS_INFO("uv_mission: finished with '%s': %zu of %zu rail sets treated\n%s", outcome.c_str(), mission.done().size(),
             targets.size(), r.data.c_str());
  };
  hooks.exit = [] { ros::shutdown(); };
  UvMissionRunner runner(mission, io, settings.exit_when_done, hooks);
  using Trigger = std_srvs::Trigger;
  ros::ServiceServer start_srv = pnh.advertiseService<Trigger::Request, Trigger::Response>(
      "start", [&](Trigger::Request&, Trigger::Response& res) {
        res.message = runner.start();
        res.success = res.message == "started";
        return true;
      });
  ros::ServiceServer stop_srv =
      pnh.advertiseService<Trigger::Request, Trigger::Response>("stop", [&](Trigger::Request&, Trigger::Response& res) {
        bool was_running = false;
        res.message = runner.stop(&was_running);
        res.success = was_running;
        return true;
      });
  ros::AsyncSpinner spinner(3);
  spinner.start();
  if (settings.autostart) runner.start();
  ros::waitForShutdown();
  runner.shutdown();
}

}  // namespace
}  // namespace greenhouse_rail_nav

int main(int argc, char** argv) {
  namespace grn = greenhouse_rail_nav;
  ros::init(argc, argv, "uv_mission");
  ros::NodeHandle nh, pnh("~");
  try {
    const grn::NodeSettings settings = grn::readSettings(pnh);
    if (settings.wait_for_rail_sets_s > 0.0 && !grn::waitForRailSets(nh, settings.wait_for_rail_sets_s)) return 1;
    grn::RailSetFile sets;
    std::string error;
    if (!grn::loadRailSetFile(settings.rail_sets_file, &sets, &error)) {
      ROS_FATAL("uv_mission: %s", error.c_str());
      return 1;
    }
    std::vector<grn::MissionTarget> targets = grn::missionTargets(sets);
    grn::setRailLengths(settings.rail_sets_file, settings.rail_length_m, &targets);
    ROS_INFO("uv_mission: %zu rail sets in %s", targets.size(), settings.rail_sets_file.c_str());
    grn::runMission(nh, pnh, settings, targets);
  } catch (const thorvald_common::ParamError& e) {
    ROS_FATAL("%s", e.what());
    return 1;
  } catch (const std::exception& e) {
    ROS_FATAL("uv_mission: %s", e.what());
    return 1;
  }
  return 0;
}
