// uv_mission: the greenhouse UV-treatment mission (UvMission) on ROS. It talks to navigation only through the
// move_base action (this workspace's headland navigator or a real move_base), reads the rail detector, the
// surface monitor, odometry, the lidar and the bumper's lock, and drives through nav_vel (the mux).
#include <actionlib/client/simple_action_client.h>
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
#include <thorvald_common/param_reader.h>
#include <thorvald_state_machine/ros/status_publisher.h>
#include <yaml-cpp/yaml.h>

#include <atomic>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "greenhouse_rail_nav/RailDetectionStatus.h"
#include "greenhouse_rail_nav/SurfaceState.h"
#include "greenhouse_rail_nav/rail_set_file.h"
#include "greenhouse_rail_nav/uv_mission.h"
#include "thorvald_map/ros/conversions.h"

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
  struct Config {
    std::string map_frame = "map", base_frame = "base_link";
    double rate_hz = 50.0, odom_timeout_s = 0.5, scan_half_width_rad = 0.05;
  };

  RosMissionIO(ros::NodeHandle& nh, const Config& c)
      : cfg_(c), rate_(c.rate_hz), tf_listener_(tf_), move_base_(nh, "move_base", true) {
    odom_sub_ = nh.subscribe("odometry/base_raw", 5, &RosMissionIO::onOdom, this);
    rail_sub_ = nh.subscribe("rail_detection", 5, &RosMissionIO::onRail, this);
    surface_sub_ = nh.subscribe("surface_monitor/state", 5, &RosMissionIO::onSurface, this);
    scan_sub_ = nh.subscribe("scan", 2, &RosMissionIO::onScan, this);
    bumper_sub_ = nh.subscribe("bumper/lock", 5, &RosMissionIO::onBumper, this);
    cmd_pub_ = nh.advertise<geometry_msgs::Twist>("nav_vel", 5);
    lights_pub_ = nh.advertise<std_msgs::Bool>("uv_lights", 1, true);
    initialpose_pub_ = nh.advertise<geometry_msgs::PoseWithCovarianceStamped>("initialpose", 1);
    std_msgs::Bool off;
    lights_pub_.publish(off);
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

  Config cfg_;
  ros::Rate rate_;
  std::mutex mutex_;
  thorvald_base::Pose2D odom_;
  ros::Time odom_stamp_;
  RailObservation rail_;
  SurfaceReading surface_;
  double forward_range_ = std::numeric_limits<double>::quiet_NaN();
  bool bumper_locked_ = false, lights_ = false;
  bool nav_failed_now_ = false;
  std::string nav_error_;
  tf2_ros::Buffer tf_;
  tf2_ros::TransformListener tf_listener_;
  MoveBaseClient move_base_;
  ros::Subscriber odom_sub_, rail_sub_, surface_sub_, scan_sub_, bumper_sub_;
  ros::Publisher cmd_pub_, lights_pub_, initialpose_pub_;
};

std::set<int> loadProgress(const std::string& path) {
  std::set<int> done;
  if (path.empty()) return done;
  std::ifstream in(path);
  if (!in) return done;
  const YAML::Node n = YAML::Load(in);
  if (n["treated"] && n["treated"].IsSequence())
    for (const auto& v : n["treated"]) done.insert(v.as<int>());
  return done;
}

void saveProgress(const std::string& path, const std::set<int>& done) {
  if (path.empty()) return;
  std::ofstream out(path);
  out << "# Rail sets the UV mission has treated; a restarted mission skips them. Delete to start over.\ntreated: [";
  bool first = true;
  for (int i : done) {
    out << (first ? "" : ", ") << i;
    first = false;
  }
  out << "]\n";
}

std::string reportText(const UvMission& m) {
  std::ostringstream o;
  o << "rail_set,treated,result,align_attempts,entry_attempts,searches,rail_length_m,lights_on_s,speed_mean_mps,"
       "speed_std_mps,duration_s\n";
  for (const auto& r : m.reports())
    o << r.index << "," << (r.treated ? 1 : 0) << ",\"" << r.result << "\"," << r.align_attempts << ","
      << r.entry_attempts << "," << r.searches << "," << r.rail_length_m << "," << r.lights_on_s << ","
      << r.speed_mean_mps << "," << r.speed_std_mps << "," << r.duration_s << "\n";
  return o.str();
}

}  // namespace
}  // namespace greenhouse_rail_nav

int main(int argc, char** argv) {
  namespace grn = greenhouse_rail_nav;
  ros::init(argc, argv, "uv_mission");
  ros::NodeHandle nh, pnh("~");
  try {
    thorvald_common::ParamReader params(pnh);
    using R = thorvald_common::ParamRange;
    grn::UvMissionParams p;
    const std::string file = params.text("rail_sets_file", "");
    const std::string progress_file = params.text("progress_file", "");
    const bool autostart = params.flag("autostart", true);
    const bool exit_when_done = params.flag("exit_when_done", false);
    const double wait_for_rail_sets_s = params.number("wait_for_rail_sets", 0.0, R::closed(0.0, 3600.0), "s");
    grn::RosMissionIO::Config io_cfg;
    io_cfg.map_frame = params.text("map_frame", io_cfg.map_frame);
    io_cfg.base_frame = params.text("base_frame", io_cfg.base_frame);
    io_cfg.rate_hz = params.number("control_rate", io_cfg.rate_hz, R::aboveUpTo(1.0, 200.0), "Hz");
    io_cfg.odom_timeout_s = params.number("odom_timeout", io_cfg.odom_timeout_s, R::above(0.0), "s");
    p.alignment.approach_x_m = params.number("approach_x", p.alignment.approach_x_m, R::closed(-5.0, -0.2), "m");
    p.alignment.y_limit_m = params.number("y_limit", p.alignment.y_limit_m, R::aboveUpTo(0.0, 0.1), "m");
    p.alignment.yaw_limit_rad = params.number("yaw_limit", p.alignment.yaw_limit_rad, R::aboveUpTo(0.0, 0.2), "rad");
    p.alignment.max_turn_rad = params.number("max_turn", p.alignment.max_turn_rad, R::closed(0.1, 1.4), "rad");
    p.motion.max_speed_mps = params.number("align_speed", p.motion.max_speed_mps, R::aboveUpTo(0.0, 1.0), "m/s");
    p.motion.max_turn_rate_rps =
        params.number("turn_rate", p.motion.max_turn_rate_rps, R::aboveUpTo(0.0, 2.0), "rad/s");
    p.motion.response_time_s = params.number("response_time", p.motion.response_time_s, R::closed(0.0, 1.0), "s");
    p.rail_run.treat_speed_mps =
        params.number("treat_speed", p.rail_run.treat_speed_mps, R::aboveUpTo(0.0, 1.5), "m/s");
    p.rail_run.return_speed_mps =
        params.number("return_speed", p.rail_run.return_speed_mps, R::aboveUpTo(0.0, 1.5), "m/s");
    p.rail_run.end_wall_range_m = params.number("end_wall_range", p.rail_run.end_wall_range_m, R::above(0.0), "m");
    p.rail_run.slow_fraction = params.number("slow_fraction", p.rail_run.slow_fraction, R::closed(0.1, 0.99));
    p.nav_timeout_s = params.number("nav_timeout", p.nav_timeout_s, R::above(0.0), "s");
    p.detect_timeout_s = params.number("detect_timeout", p.detect_timeout_s, R::above(0.0), "s");
    p.search_step_rad = params.number("search_step", p.search_step_rad, R::aboveUpTo(0.0, 1.0), "rad");
    p.search_limit_rad = params.number("search_limit", p.search_limit_rad, R::aboveUpTo(0.0, 3.14), "rad");
    p.max_align_attempts = params.integer("max_align_attempts", p.max_align_attempts, 1, 50);
    p.enter_speed_mps = params.number("enter_speed", p.enter_speed_mps, R::aboveUpTo(0.0, 0.3), "m/s");
    p.enter_max_distance_m = params.number("enter_max_distance", p.enter_max_distance_m, R::above(0.0), "m");
    p.on_rails_margin_m = params.number("on_rails_margin", p.on_rails_margin_m, R::closed(0.0, 1.0), "m");
    p.enter_line_frequency_rps =
        params.number("enter_line_frequency", p.enter_line_frequency_rps, R::closed(0.0, 3.0), "rad/s");
    p.secure_wait_s = params.number("secure_wait", p.secure_wait_s, R::aboveUpTo(0.0, 10.0), "s");
    p.recover_reverse_max_m = params.number("recover_reverse_max", p.recover_reverse_max_m, R::closed(0.0, 5.0), "m");
    params.finish();
    const std::string problems = p.validate();
    if (!problems.empty()) throw thorvald_common::ParamError("uv_mission: " + problems);
    if (file.empty())
      throw thorvald_common::ParamError("uv_mission: ~rail_sets_file is required (map_analyzer's output)");
    if (wait_for_rail_sets_s > 0.0) {
      // map_analyzer, started together with the mission, writes the file before it publishes rail_targets
      // (latched): the file is read once that message has come, so a file left by an earlier run is not taken.
      ROS_INFO("uv_mission: waiting up to %.0f s for map_analyzer's rail_targets", wait_for_rail_sets_s);
      const auto good =
          ros::topic::waitForMessage<geometry_msgs::PoseArray>("rail_targets", nh, ros::Duration(wait_for_rail_sets_s));
      if (!good) {
        ROS_FATAL("uv_mission: no rail_targets from map_analyzer within %.0f s (wait_for_rail_sets)",
                  wait_for_rail_sets_s);
        return 1;
      }
      if (good->poses.empty()) {
        // No good set: either all are uncertain (the file lists them) or nothing was found (no file is written,
        // and one left by an earlier run must not be read).
        const auto uncertain =
            ros::topic::waitForMessage<geometry_msgs::PoseArray>("rail_targets_uncertain", nh, ros::Duration(5.0));
        if (!uncertain || uncertain->poses.empty()) {
          ROS_FATAL("uv_mission: map_analyzer found no rail sets in the map (see its status)");
          return 1;
        }
      }
    }
    grn::RailSetFile sets;
    std::string error;
    if (!grn::loadRailSetFile(file, &sets, &error)) {
      ROS_FATAL("uv_mission: %s", error.c_str());
      return 1;
    }
    std::vector<grn::MissionTarget> targets;
    for (const auto& s : sets.rail_sets) targets.push_back({s.index, s.target_pose, s.good, s.reason});
    ROS_INFO("uv_mission: %zu rail sets in %s", targets.size(), file.c_str());

    grn::RosMissionIO io(nh, io_cfg);
    grn::UvMission mission(io, p, targets);
    mission.markDone(grn::loadProgress(progress_file));
    thorvald_state_machine::StatusPublisher status(nh, mission.machine(), "mission/status", 1.0);
    ros::Publisher report_pub = nh.advertise<std_msgs::String>("mission/report", 1, true);
    std::atomic<bool> running{false};
    std::thread worker;
    std::mutex worker_mutex;
    auto start = [&]() -> std::string {
      std::lock_guard<std::mutex> l(worker_mutex);
      if (running) return "already running";
      if (worker.joinable()) worker.join();
      running = true;
      worker = std::thread([&] {
        std::string outcome;
        try {
          outcome = mission.run();
        } catch (const std::exception& e) {
          outcome = "aborted";
          ROS_ERROR("uv_mission: the mission stopped on an error: %s", e.what());
          io.commandTwist(0.0, 0.0);
          io.setLights(false);
        }
        grn::saveProgress(progress_file, mission.done());
        std_msgs::String r;
        r.data = grn::reportText(mission);
        report_pub.publish(r);
        if (!mission.stopReason().empty())
          ROS_ERROR("uv_mission: stopped before the end, the robot needs a person: %s", mission.stopReason().c_str());
        // The report covers this run; done() also holds the sets treated by earlier runs.
        ROS_INFO("uv_mission: finished with '%s': %zu of %zu rail sets treated\n%s", outcome.c_str(),
                 mission.done().size(), targets.size(), r.data.c_str());
        running = false;
        if (exit_when_done && outcome != thorvald_state_machine::kPreempted) ros::shutdown();
      });
      return "started";
    };
    ros::ServiceServer start_srv = pnh.advertiseService<std_srvs::Trigger::Request, std_srvs::Trigger::Response>(
        "start", [&](std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
          res.message = start();
          res.success = res.message == "started";
          return true;
        });
    ros::ServiceServer stop_srv = pnh.advertiseService<std_srvs::Trigger::Request, std_srvs::Trigger::Response>(
        "stop", [&](std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
          mission.requestPreempt();
          res.success = running;
          res.message = running ? "stopping; ~start resumes at the first rail set not treated" : "not running";
          return true;
        });
    ros::AsyncSpinner spinner(3);
    spinner.start();
    if (autostart) start();
    ros::waitForShutdown();
    mission.requestPreempt();
    if (worker.joinable()) worker.join();
  } catch (const thorvald_common::ParamError& e) {
    ROS_FATAL("%s", e.what());
    return 1;
  } catch (const std::exception& e) {
    ROS_FATAL("uv_mission: %s", e.what());
    return 1;
  }
  return 0;
}
