// headland_navigator: move_base's interface (move_base_msgs/MoveBaseAction on `move_base`,
// `move_base_simple/goal`) over a global A* plan on the map plus the keep-out grid, inflated for the robot's
// footprint, and a path follower (omnidirectional where every drive steers, differential otherwise) that stops for
// lidar obstacles and replans. Commands go to `nav_vel`. Thin shell around Costmap, planPath and PathFollower.
#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <actionlib/server/simple_action_server.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/Twist.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/String.h>
#include <tf2_ros/transform_listener.h>
#include <thorvald_base/ros/param_reader.h>

#include "ros_conversions.h"
#include "scan_frames.h"
#include "thorvald_base/ros/robot_config_params.h"
#include "thorvald_navigation/costmap.h"
#include "thorvald_navigation/grid_planner.h"
#include "thorvald_navigation/localization_gate.h"
#include "thorvald_navigation/path_follower.h"

namespace thorvald_navigation {
namespace {

struct Settings {
  std::string global_frame = "map", base_frame = "base_link";
  std::string keep_out_topic = "keep_out_map";
  std::string localization_status_topic = "map_localizer/status";  // empty: no status read (amcl)
  double controller_frequency = 20.0;
  double footprint_padding = 0.05;
  std::vector<double> footprint;       // flat x0 y0 x1 y1 ...; empty: from the robot file
  std::string drive_mode = "auto";     // auto | omnidirectional | differential
  double obstacle_range = 3.0;         // lidar points farther than this are not obstacles [m]
  double obstacle_check_ahead = 1.5;   // path length checked for obstacles [m]
  double obstacle_wait = 10.0;         // give up when blocked for this long [s]
  double planner_patience = 5.0;       // give up when no pose/plan for this long [s]
  double settle_time = 0.5;            // after arriving, stand still this long before checking the pose [s]
  int goal_corrections = 3;            // re-approaches when the settled pose is outside the tolerances
  double final_approach = 0.3;         // differential: the last metres driven straight along the goal heading [m]
  double obstacle_update_rate = 10.0;  // lidar obstacles enter the costmap (and its inflation) at most this often [Hz]
  double scan_max_age = 0.5;           // obstacles older than this are forgotten [s]
  CostmapParams costmap;
  PlannerParams planner;
  FollowerParams follower;
  LocalizationGateParams gate;
};

Footprint makeFootprint(const std::vector<double>& flat, double padding) {
  Footprint fp;
  for (std::size_t i = 0; i + 1 < flat.size(); i += 2) {
    Eigen::Vector2d p(flat[i], flat[i + 1]);
    // Pad outwards from the polygon's centroid direction (exact for rectangles around base_link's box).
    p += Eigen::Vector2d(p.x() >= 0 ? padding : -padding, p.y() >= 0 ? padding : -padding);
    fp.polygon.push_back(p);
  }
  return fp;
}

/// Reads and checks the node's parameters; false with the reason in `error` when one is wrong.
bool loadSettings(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, Settings* s, std::string* error) {
  using R = thorvald_base::ParamRange;
  auto check = [](const std::string& problem) {
    if (!problem.empty()) throw thorvald_base::ParamError("headland_navigator: " + problem);
  };
  try {
    thorvald_base::ParamReader r(pnh, "headland_navigator");
    s->global_frame = r.text("global_frame", s->global_frame);
    s->base_frame = r.text("robot_base_frame", s->base_frame);
    s->keep_out_topic = r.text("keep_out_topic", s->keep_out_topic);
    s->localization_status_topic = r.text("localization_status_topic", s->localization_status_topic);
    s->gate.lost_wait_s = r.number("localization_lost_wait", s->gate.lost_wait_s, R::aboveUpTo(0.0, 3600.0), "s");
    s->gate.uncertain_wait_s =
        r.number("localization_uncertain_wait", s->gate.uncertain_wait_s, R::aboveUpTo(0.0, 3600.0), "s");
    s->controller_frequency = r.number("controller_frequency", s->controller_frequency, R::aboveUpTo(0.0, 200.0), "Hz");
    s->footprint_padding = r.number("footprint_padding", s->footprint_padding, R::closed(0.0, 1.0), "m");
    s->footprint = r.numbers("footprint", s->footprint, R::closed(-20.0, 20.0), "m", 0, 200);
    s->drive_mode = r.choice("drive_mode", s->drive_mode, {"auto", "omnidirectional", "differential"});
    s->obstacle_range = r.number("obstacle_range", s->obstacle_range, R::above(0.0), "m");
    s->obstacle_check_ahead = r.number("obstacle_check_ahead", s->obstacle_check_ahead, R::above(0.0), "m");
    s->obstacle_wait = r.number("obstacle_wait", s->obstacle_wait, R::above(0.0), "s");
    s->planner_patience = r.number("planner_patience", s->planner_patience, R::above(0.0), "s");
    s->settle_time = r.number("settle_time", s->settle_time, R::closed(0.0, 5.0), "s");
    s->goal_corrections = r.integer("goal_corrections", s->goal_corrections, 0, 20);
    s->final_approach = r.number("final_approach", s->final_approach, R::closed(0.0, 2.0), "m");
    s->obstacle_update_rate = r.number("obstacle_update_rate", s->obstacle_update_rate, R::aboveUpTo(0.0, 100.0), "Hz");
    s->scan_max_age = r.number("scan_max_age", s->scan_max_age, R::above(0.0), "s");
    s->costmap.inflation_radius_m = r.number("inflation_radius", s->costmap.inflation_radius_m, R::atLeast(0.0), "m");
    // 0: half the footprint's width (+ padding), set below.
    s->costmap.planning_radius_m = r.number("planning_radius", 0.0, R::atLeast(0.0), "m");
    s->costmap.cost_scaling = r.number("cost_scaling_factor", s->costmap.cost_scaling, R::above(0.0), "1/m");
    s->costmap.unknown_is_blocked = !r.flag("allow_unknown", !s->costmap.unknown_is_blocked);
    s->costmap.known_structure_tolerance_m =
        r.number("known_structure_tolerance", s->costmap.known_structure_tolerance_m, R::closed(0.0, 1.0), "m");
    s->planner.cost_weight = r.number("cost_weight", s->planner.cost_weight, R::atLeast(0.0));
    auto& f = s->follower;
    f.max_speed_mps = r.number("max_vel_x", f.max_speed_mps, R::above(0.0), "m/s");
    f.max_yaw_rate_radps = r.number("max_vel_theta", f.max_yaw_rate_radps, R::above(0.0), "rad/s");
    f.max_accel_mps2 = r.number("acc_lim_x", f.max_accel_mps2, R::above(0.0), "m/s^2");
    f.max_yaw_accel_radps2 = r.number("acc_lim_theta", f.max_yaw_accel_radps2, R::above(0.0), "rad/s^2");
    f.xy_tolerance_m = r.number("xy_goal_tolerance", f.xy_tolerance_m, R::above(0.0), "m");
    f.yaw_tolerance_rad = r.number("yaw_goal_tolerance", f.yaw_tolerance_rad, R::above(0.0), "rad");
    f.lookahead_m = r.number("lookahead", f.lookahead_m, R::above(0.0), "m");
    f.rotate_in_place_rad = r.number("rotate_in_place_angle", f.rotate_in_place_rad, R::closed(0.0, 3.1416), "rad");
    f.arrive_fraction = r.number("arrive_fraction", f.arrive_fraction, R::closed(0.05, 1.0));
    r.finish();
    if (!s->footprint.empty() && (s->footprint.size() < 6 || s->footprint.size() % 2 != 0))
      check("~footprint must be a flat list x0 y0 x1 y1 ... of at least 3 points, got " +
            std::to_string(s->footprint.size()) + " numbers");
    if (s->footprint.empty()) {
      // The robot file in the robot's namespace: the box around wheels, casters and corners.
      thorvald_base::RobotConfig cfg;
      try {
        cfg = thorvald_base::robotConfigFromParams(nh);
      } catch (const std::exception& e) {
        check("no ~footprint and no usable robot file in " + nh.getNamespace() + ": " + e.what());
      }
      double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
      auto grow = [&](double x, double y, double rx, double ry) {
        x0 = std::min(x0, x - rx);
        x1 = std::max(x1, x + rx);
        y0 = std::min(y0, y - ry);
        y1 = std::max(y1, y + ry);
      };
      bool all_steered = !cfg.drives.empty();
      for (const auto& d : cfg.drives) {
        grow(d.x, d.y, d.r_wheel, 0.5 * d.w_wheel);
        all_steered = all_steered && d.type == 0;
      }
      for (const auto& c : cfg.casters) grow(c.x, c.y, c.r_wheel + c.offset, 0.5 * c.w_wheel);
      for (const auto& c : cfg.passive_wheels) grow(c.x, c.y, c.r_wheel, 0.5 * c.w_wheel);
      for (const auto& c : cfg.corners) grow(c.x, c.y, 0.05, 0.05);
      s->footprint = {x0, y0, x1, y0, x1, y1, x0, y1};
      if (s->drive_mode == "auto")
        s->drive_mode = all_steered && cfg.passive_wheels.empty() ? "omnidirectional" : "differential";
    }
    if (s->drive_mode == "auto") s->drive_mode = "differential";
    f.omnidirectional = s->drive_mode == "omnidirectional";
    if (s->costmap.planning_radius_m <= 0.0)
      s->costmap.planning_radius_m = makeFootprint(s->footprint, s->footprint_padding).halfWidth();
    s->costmap.inflation_radius_m = std::max(s->costmap.inflation_radius_m, s->costmap.planning_radius_m);
    check(s->costmap.validate());
    check(s->planner.validate());
    check(f.validate());
    check(s->gate.validate());
  } catch (const thorvald_base::ParamError& e) {
    *error = e.what();
    return false;
  }
  return true;
}

using ActionServer = actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>;

class HeadlandNavigatorNode {
 public:
  HeadlandNavigatorNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const Settings& s)
      : s_(s),
        footprint_(makeFootprint(s.footprint, s.footprint_padding)),
        follower_(s.follower),
        gate_(s.gate),
        tf_listener_(tf_buffer_),
        frames_(tf_buffer_),
        updater_(nh, pnh),
        server_(nh, "move_base", false) {
    cmd_pub_ = nh.advertise<geometry_msgs::Twist>("nav_vel", 1);
    plan_pub_ = pnh.advertise<nav_msgs::Path>("plan", 1, true);
    costmap_pub_ = pnh.advertise<nav_msgs::OccupancyGrid>("costmap", 1, true);
    map_sub_ = nh.subscribe("map", 1, &HeadlandNavigatorNode::onMap, this);
    keep_out_sub_ = nh.subscribe(s_.keep_out_topic, 1, &HeadlandNavigatorNode::onKeepOut, this);
    scan_sub_ = nh.subscribe("scan", 1, &HeadlandNavigatorNode::onScan, this);
    simple_goal_sub_ = nh.subscribe("move_base_simple/goal", 1, &HeadlandNavigatorNode::onSimpleGoal, this);
    if (!s_.localization_status_topic.empty())
      status_sub_ = nh.subscribe(s_.localization_status_topic, 5, &HeadlandNavigatorNode::onLocalizerStatus, this);
    simple_client_pub_ = nh.advertise<move_base_msgs::MoveBaseActionGoal>("move_base/goal", 1);
    server_.registerGoalCallback([this] { onGoal(); });
    server_.registerPreemptCallback([this] { onPreempt(); });
    server_.start();
    timer_ = nh.createTimer(ros::Duration(1.0 / s_.controller_frequency), &HeadlandNavigatorNode::onTimer, this);
    updater_.setHardwareID("headland_navigator");
    updater_.add("navigation", this, &HeadlandNavigatorNode::diagnose);
    ROS_INFO("headland_navigator: %s, footprint %zu points (half width %.2f m), planning radius %.2f m",
             s_.drive_mode.c_str(), footprint_.polygon.size(), footprint_.halfWidth(), s_.costmap.planning_radius_m);
  }

 private:
  void rebuildCostmap() {
    if (map_.width == 0) return;
    costmap_ = std::make_unique<Costmap>(map_, keep_out_, s_.costmap);
    costmap_->setObstacles(obstacles_);
    publishCostmap();
  }

  void publishCostmap() {
    if (!costmap_ || costmap_pub_.getNumSubscribers() == 0) return;
    nav_msgs::OccupancyGrid m = toGridMessage(costmap_->toDisplayGrid(), s_.global_frame);
    m.header.stamp = ros::Time::now();
    costmap_pub_.publish(m);
  }

  void onMap(const nav_msgs::OccupancyGrid::ConstPtr& msg) {
    Grid2D g;
    const std::string e = fromGridMessage(*msg, &g);
    if (!e.empty()) {
      ROS_ERROR_STREAM("headland_navigator: map rejected: " << e);
      return;
    }
    map_ = std::move(g);
    rebuildCostmap();
  }

  void onKeepOut(const nav_msgs::OccupancyGrid::ConstPtr& msg) {
    Grid2D g;
    const std::string e = fromGridMessage(*msg, &g);
    if (!e.empty()) {
      ROS_ERROR_STREAM("headland_navigator: keep-out grid rejected: " << e);
      return;
    }
    keep_out_ = std::move(g);
    ROS_INFO("headland_navigator: keep-out grid %d x %d received", keep_out_.width, keep_out_.height);
    rebuildCostmap();
  }

  void onScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
    std::string error;
    Pose2D sensor_in_map;
    if (!frames_.lookup(s_.global_frame, msg->header.frame_id, msg->header.stamp, 0.05, &sensor_in_map, &error)) {
      ROS_WARN_STREAM_THROTTLE(5.0, "headland_navigator: scan not used for obstacles: " << error);
      return;
    }
    ScanPoints pts;
    error = scanToPoints(*msg, sensor_in_map, s_.obstacle_range, &pts);
    if (!error.empty()) {
      ROS_WARN_STREAM_THROTTLE(5.0, "headland_navigator: scan rejected: " << error);
      return;
    }
    obstacles_ = std::move(pts.hits);
    last_scan_ = ros::Time::now();
    // Re-inflating the whole costmap costs milliseconds: not for every scan of a 40 Hz lidar.
    if (costmap_ && (last_obstacle_update_.isZero() || last_scan_ < last_obstacle_update_ ||
                     (last_scan_ - last_obstacle_update_).toSec() >= 1.0 / s_.obstacle_update_rate)) {
      costmap_->setObstacles(obstacles_);
      last_obstacle_update_ = last_scan_;
    }
  }

  // The localiser's status (map_localizer's ~status, latched, sent on every change).
  void onLocalizerStatus(const std_msgs::String::ConstPtr& msg) {
    LocalizerState state;
    if (!parseLocalizerState(msg->data, &state)) {
      ++bad_statuses_;
      ROS_WARN_STREAM_THROTTLE(5.0, "headland_navigator: localiser status '" << msg->data << "' not understood");
      return;
    }
    if (state != gate_.state()) ROS_INFO_STREAM("headland_navigator: localiser " << localizerStateName(state));
    gate_.setStatus(state, ros::Time::now().toSec());
  }

  // Holds the robot while the localiser is lost, aborts the goal when it stays lost. True when it may drive.
  bool localizationAllows(const GateVerdict& v) {
    if (v.action == GateAction::kAbort) {
      abort(v.reason);
      return false;
    }
    if (v.action == GateAction::kHold) {
      stopRobot();
      if (!holding_) ROS_WARN_STREAM("headland_navigator: " << v.reason);
      holding_ = true;
      hold_reason_ = v.reason;
      return false;
    }
    return true;
  }

  void onSimpleGoal(const geometry_msgs::PoseStamped::ConstPtr& msg) {
    // As move_base does: republish as an action goal so that one path handles both.
    move_base_msgs::MoveBaseActionGoal g;
    g.header.stamp = ros::Time::now();
    g.goal_id.stamp = g.header.stamp;
    g.goal.target_pose = *msg;
    simple_client_pub_.publish(g);
  }

  void onGoal() {
    const auto goal = server_.acceptNewGoal();
    const geometry_msgs::PoseStamped& target = goal->target_pose;
    Pose2D g = fromPose(target.pose);
    const std::string frame = target.header.frame_id.empty() ? s_.global_frame : target.header.frame_id;
    std::string error;
    if (g.finite() && frame != s_.global_frame) {
      Pose2D frame_in_map;
      if (!frames_.lookup(s_.global_frame, frame, ros::Time(0), 0.2, &frame_in_map, &error)) {
        abort("goal frame '" + frame + "' cannot be transformed to '" + s_.global_frame + "': " + error);
        return;
      }
      g = frame_in_map * g;
    }
    if (!g.finite()) {
      abort("goal pose is not finite (or its quaternion is zero)");
      return;
    }
    goal_ = g;
    active_ = true;
    need_plan_ = true;
    blocked_since_ = ros::Time();
    arrived_at_ = ros::Time();
    corrections_ = 0;
    to_pre_goal_ = false;
    holding_ = false;
    started_ = ros::Time::now();
    ROS_INFO("headland_navigator: new goal (%.2f, %.2f, %.2f)", g.x, g.y, g.yaw);
  }

  void onPreempt() {
    stopRobot();
    active_ = false;
    server_.setPreempted(move_base_msgs::MoveBaseResult(), "cancelled");
    ROS_INFO("headland_navigator: goal cancelled, robot stopped");
  }

  void abort(const std::string& reason) {
    stopRobot();
    active_ = false;
    last_failure_ = reason;
    ROS_WARN_STREAM("headland_navigator: goal aborted: " << reason);
    if (server_.isActive()) server_.setAborted(move_base_msgs::MoveBaseResult(), reason);
  }

  void stopRobot() {
    follower_.stop();
    cmd_pub_.publish(geometry_msgs::Twist());
  }

  bool plan(const Pose2D& pose, std::string* error) {
    const Blocker at_goal = costmap_->footprintBlocker(goal_, footprint_);
    if (at_goal != Blocker::kNone) {
      *error = std::string("goal refused: the robot would overlap ") + blockerName(at_goal);
      return false;
    }
    const PlanResult r = planPath(*costmap_, {pose.x, pose.y}, {goal_.x, goal_.y}, s_.planner);
    if (!r.ok) {
      *error = "goal refused: " + r.error;
      return false;
    }
    path_ = withFinalApproach(r.path);
    follower_.setPath(path_, goal_);
    nav_msgs::Path msg;
    msg.header.stamp = ros::Time::now();
    msg.header.frame_id = s_.global_frame;
    for (std::size_t i = 0; i < path_.size(); ++i) {
      geometry_msgs::PoseStamped p;
      p.header = msg.header;
      const Eigen::Vector2d d = i + 1 < path_.size() ? Eigen::Vector2d(path_[i + 1] - path_[i]) : Eigen::Vector2d(0, 0);
      p.pose = toPose({path_[i].x(), path_[i].y(), i + 1 < path_.size() ? std::atan2(d.y(), d.x()) : goal_.yaw});
      msg.poses.push_back(p);
    }
    plan_pub_.publish(msg);
    ++plans_;
    return true;
  }

  // A differential robot turning on the spot at the goal moves base_link by a few centimetres (its turning centre is
  // not exactly base_link's on a real floor): it ends its path with `final_approach` metres straight along the goal
  // heading, so that the final turn is small. Kept out when that stretch would touch a wall, keep-out or obstacle.
  std::vector<Eigen::Vector2d> withFinalApproach(std::vector<Eigen::Vector2d> path) const {
    if (s_.follower.omnidirectional || s_.final_approach <= 0.0 || path.empty()) return path;
    const Eigen::Vector2d goal(goal_.x, goal_.y), heading(std::cos(goal_.yaw), std::sin(goal_.yaw));
    const Eigen::Vector2d pre = goal - s_.final_approach * heading;
    for (double d = 0.0; d <= s_.final_approach + 1e-9; d += 0.1) {
      const Eigen::Vector2d p = pre + d * heading;
      if (costmap_->footprintBlocker({p.x(), p.y(), goal_.yaw}, footprint_) != Blocker::kNone) return path;
    }
    // Drop the plan's points that lie within the approach stretch, then go through its start.
    while (path.size() > 1 && (path.back() - goal).norm() < s_.final_approach + 0.05) path.pop_back();
    if ((path.back() - goal).norm() < s_.final_approach + 0.05) path.clear();
    path.push_back(pre);
    path.push_back(goal);
    return path;
  }

  // Is a lidar obstacle (not a known wall or the keep-out zone) under the footprint along the next
  // obstacle_check_ahead metres of the path?
  bool obstacleAhead(const Pose2D& pose) const {
    return sweptObstacleDistance(*costmap_, footprint_, pose, path_, follower_.progressIndex() + 1,
                                 s_.obstacle_check_ahead, s_.follower.omnidirectional) >= 0.0;
  }

  void onTimer(const ros::TimerEvent& ev) {
    updater_.update();
    if (!active_) return;
    if (!server_.isActive()) {
      active_ = false;
      return;
    }
    const ros::Time now = ros::Time::now();
    if (!last_scan_.isZero() && (now - last_scan_).toSec() > s_.scan_max_age && !obstacles_.empty()) {
      obstacles_.clear();  // the lidar went quiet: do not steer around ghosts, but say so
      if (costmap_) costmap_->setObstacles(obstacles_);
      ROS_WARN_THROTTLE(5.0, "headland_navigator: no recent scan: obstacle layer cleared");
    }
    std::string error;
    Pose2D pose;
    if (!costmap_ || !frames_.lookup(s_.global_frame, s_.base_frame, ros::Time(0), 0.0, &pose, &error)) {
      stopRobot();
      if ((now - started_).toSec() > s_.planner_patience)
        abort(costmap_ ? "no robot pose in " + s_.global_frame + ": " + error : "no map received on 'map'");
      return;
    }
    const bool arriving = follower_.state() == FollowState::kArrived && !to_pre_goal_ && !arrived_at_.isZero();
    if (!arriving) {
      if (!localizationAllows(gate_.whileDriving(now.toSec(), started_.toSec()))) return;
      if (holding_) {  // relocalised: the pose may have moved, plan again from it
        holding_ = false;
        need_plan_ = true;
        ++relocalisation_waits_;
        ROS_INFO("headland_navigator: localiser %s again: replanning", localizerStateName(gate_.state()));
      }
    }
    if (need_plan_) {
      if (!plan(pose, &error)) {
        // A goal blocked by the map or keep-out is refused at once; one blocked by lidar obstacles waits.
        const bool obstacle = error.find("lidar") != std::string::npos;
        if (!obstacle || blocked_since_.isZero()) blocked_since_ = now;
        if (!obstacle || (now - blocked_since_).toSec() > s_.obstacle_wait) {
          abort(error);
          return;
        }
        stopRobot();
        return;
      }
      need_plan_ = false;  // blocked_since_ stays: a new plan the obstacle still blocks does not restart the wait
    }
    if (obstacleAhead(pose)) {
      stopRobot();
      if (blocked_since_.isZero()) {
        blocked_since_ = now;
        ROS_WARN("headland_navigator: obstacle ahead: stopped, replanning");
      }
      ++obstacle_stops_;
      need_plan_ = true;
      if ((now - blocked_since_).toSec() > s_.obstacle_wait) abort("path blocked by an obstacle for too long");
      return;
    }
    blocked_since_ = ros::Time();
    const double dt =
        ev.last_real.isZero() ? 1.0 / s_.controller_frequency : std::min(0.5, (ev.current_real - ev.last_real).toSec());
    const Twist2D t = follower_.step(pose, dt);
    if (follower_.state() == FollowState::kArrived) {
      // The robot still moves a little after the last command (drive response, wheel slip while turning): judge
      // the pose once it stands, and approach again while it is outside the tolerances.
      if (to_pre_goal_) {  // at the start of the final approach: now straight to the goal
        to_pre_goal_ = false;
        path_ = {pre_goal_, Eigen::Vector2d(goal_.x, goal_.y)};
        follower_.setPath(path_, goal_);
        return;
      }
      stopRobot();
      if (arrived_at_.isZero()) arrived_at_ = now;
      if ((now - arrived_at_).toSec() < s_.settle_time) return;
      // Judged only on a pose the localiser stands by: wait while it is uncertain or lost, abort when that lasts.
      if (!localizationAllows(gate_.atGoal(now.toSec(), started_.toSec(), arrived_at_.toSec() + s_.settle_time)))
        return;
      if (holding_) {
        holding_ = false;
        ++relocalisation_waits_;
        ROS_INFO("headland_navigator: localiser %s again at the goal", localizerStateName(gate_.state()));
      }
      arrived_at_ = ros::Time();
      const double err = std::hypot(pose.x - goal_.x, pose.y - goal_.y);
      const double err_yaw = normalizeAngle(pose.yaw - goal_.yaw);
      const bool within = err <= s_.follower.xy_tolerance_m && std::abs(err_yaw) <= s_.follower.yaw_tolerance_rad;
      if (!within && corrections_ < s_.goal_corrections) {
        ++corrections_;
        ROS_INFO("headland_navigator: settled %.3f m, %.3f rad off the goal: approaching again (%d of %d)", err,
                 err_yaw, corrections_, s_.goal_corrections);
        // Back off to the start of the final approach (differential) and drive it again; else straight there.
        const std::vector<Eigen::Vector2d> approach =
            withFinalApproach({Eigen::Vector2d(pose.x, pose.y), Eigen::Vector2d(goal_.x, goal_.y)});
        if (approach.size() >= 2 && (approach.end()[-2] - Eigen::Vector2d(goal_.x, goal_.y)).norm() > 1e-3) {
          pre_goal_ = approach.end()[-2];
          path_ = {Eigen::Vector2d(pose.x, pose.y), pre_goal_};
          follower_.setPath(path_, {pre_goal_.x(), pre_goal_.y(), goal_.yaw});
          to_pre_goal_ = true;
        } else {
          path_ = approach;
          follower_.setPath(path_, goal_);
        }
        return;
      }
      active_ = false;
      if (!within) {
        abort("settled " + std::to_string(err) + " m, " + std::to_string(err_yaw) + " rad off the goal after " +
              std::to_string(corrections_) + " corrections");
        return;
      }
      ROS_INFO("headland_navigator: goal reached (%.3f m, %.3f rad off, %d corrections)", err, err_yaw, corrections_);
      server_.setSucceeded(move_base_msgs::MoveBaseResult(), "goal reached");
      ++reached_;
      return;
    }
    geometry_msgs::Twist cmd;
    cmd.linear.x = t.vx;
    cmd.linear.y = t.vy;
    cmd.angular.z = t.wz;
    cmd_pub_.publish(cmd);
    move_base_msgs::MoveBaseFeedback fb;
    fb.base_position.header.stamp = now;
    fb.base_position.header.frame_id = s_.global_frame;
    fb.base_position.pose = toPose(pose);
    server_.publishFeedback(fb);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& st) {
    using D = diagnostic_msgs::DiagnosticStatus;
    if (!costmap_) {
      st.summary(D::WARN, "no map yet");
    } else if (active_ && holding_) {
      st.summary(D::WARN, hold_reason_);
    } else if (active_ && !blocked_since_.isZero()) {
      st.summary(D::WARN, "blocked by an obstacle");
    } else {
      st.summary(D::OK, active_ ? "navigating" : "idle");
    }
    st.add("drive mode", s_.drive_mode);
    st.add("keep-out grid", keep_out_.width > 0 ? "received" : "none");
    st.add("plans", plans_);
    st.add("goals reached", reached_);
    st.add("obstacle stops (cycles)", obstacle_stops_);
    if (costmap_) {
      st.add("lidar points: obstacles", costmap_->obstaclePoints());
      st.add("lidar points: known walls / keep-out", costmap_->knownStructurePoints());
    }
    st.add("localiser status", localizerStateName(gate_.state()));
    st.add("waits for relocalisation", relocalisation_waits_);
    st.add("localiser statuses not understood", bad_statuses_);
    st.add("last failure", last_failure_);
  }

  Settings s_;
  Footprint footprint_;
  PathFollower follower_;
  LocalizationGate gate_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  FrameLookup frames_;
  diagnostic_updater::Updater updater_;
  ActionServer server_;
  ros::Publisher cmd_pub_, plan_pub_, costmap_pub_, simple_client_pub_;
  ros::Subscriber map_sub_, keep_out_sub_, scan_sub_, simple_goal_sub_, status_sub_;
  ros::Timer timer_;
  Grid2D map_, keep_out_;
  std::unique_ptr<Costmap> costmap_;
  std::vector<Eigen::Vector2d> obstacles_, path_;
  Pose2D goal_;
  bool active_ = false, need_plan_ = false;
  ros::Time blocked_since_, started_, last_scan_, arrived_at_, last_obstacle_update_;
  int corrections_ = 0;
  bool to_pre_goal_ = false;  // a correction is on its way to the start of the final approach
  Eigen::Vector2d pre_goal_{0.0, 0.0};
  long plans_ = 0, reached_ = 0, obstacle_stops_ = 0, relocalisation_waits_ = 0, bad_statuses_ = 0;
  bool holding_ = false;  // stopped for the localiser
  std::string last_failure_, hold_reason_;
};

}  // namespace
}  // namespace thorvald_navigation

int main(int argc, char** argv) {
  ros::init(argc, argv, "headland_navigator");
  ros::NodeHandle nh, pnh("~");
  thorvald_navigation::Settings settings;
  std::string error;
  if (!thorvald_navigation::loadSettings(nh, pnh, &settings, &error)) {
    ROS_FATAL_STREAM(error);
    return 1;
  }
  thorvald_navigation::HeadlandNavigatorNode node(nh, pnh, settings);
  ros::spin();  // single-threaded: callbacks, the action server's callbacks and the control timer never overlap
  return 0;
}
