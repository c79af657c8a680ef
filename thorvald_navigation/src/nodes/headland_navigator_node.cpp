// headland_navigator: move_base's interface (move_base_msgs/MoveBaseAction on `move_base`,
// `move_base_simple/goal`) over a global A* plan on the map plus the keep-out grid, inflated for the robot's
// footprint, and a path follower (omnidirectional where every drive steers, differential otherwise) that stops for
// lidar obstacles and replans. Commands go to `nav_vel`. Thin shell around the library: Costmap and
// sweptObstacleDistance, planToGoal, PathFollower, ArrivalJudge and approachAgain; parameters in
// headland_navigator_settings.
#include <algorithm>
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

#include "headland_navigator_settings.h"
#include "ros_conversions.h"
#include "scan_frames.h"
#include "thorvald_navigation/costmap.h"
#include "thorvald_navigation/goal_approach.h"
#include "thorvald_navigation/grid_planner.h"
#include "thorvald_navigation/localization_gate.h"
#include "thorvald_navigation/path_follower.h"

namespace thorvald_navigation {
namespace {

using ActionServer = actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>;

class HeadlandNavigatorNode {
 public:
  HeadlandNavigatorNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const Settings& s)
      : s_(s),
        footprint_(makeFootprint(s.footprint, s.footprint_padding)),
        follower_(s.follower),
        arrival_(ArrivalParams{s.follower.xy_tolerance_m, s.follower.yaw_tolerance_rad, s.goal_corrections}),
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
    nav_msgs::OccupancyGrid m = thorvald_map::toGridMessage(costmap_->toDisplayGrid(), s_.global_frame);
    m.header.stamp = ros::Time::now();
    costmap_pub_.publish(m);
  }

  void onMap(const nav_msgs::OccupancyGrid::ConstPtr& msg) {
    thorvald_map::OccupancyGrid g;
    std::string e;
    if (!thorvald_map::fromGridMessage(*msg, &g, &e, /*unrotated=*/true)) {
      ROS_ERROR_STREAM("headland_navigator: map rejected: " << e);
      return;
    }
    map_ = std::move(g);
    rebuildCostmap();
  }

  void onKeepOut(const nav_msgs::OccupancyGrid::ConstPtr& msg) {
    thorvald_map::OccupancyGrid g;
    std::string e;
    if (!thorvald_map::fromGridMessage(*msg, &g, &e, /*unrotated=*/true)) {
      ROS_ERROR_STREAM("headland_navigator: keep-out grid rejected: " << e);
      return;
    }
    keep_out_ = std::move(g);
    ROS_INFO("headland_navigator: keep-out grid %d x %d received", keep_out_.width, keep_out_.height);
    rebuildCostmap();
  }

  void onScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
    std::string error;
    thorvald_base::Pose2D sensor_in_map;
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
    thorvald_base::Pose2D g = thorvald_map::fromPose(target.pose);
    const std::string frame = target.header.frame_id.empty() ? s_.global_frame : target.header.frame_id;
    std::string error;
    if (g.finite() && frame != s_.global_frame) {
      thorvald_base::Pose2D frame_in_map;
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
    arrival_.reset();
    last_phase_ = FollowPhase::kIdle;
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

  // Plans from `pose` to the goal and publishes the plan; false with the reason, and whether lidar obstacles alone
  // stand in the way, when there is none.
  bool plan(const thorvald_base::Pose2D& pose, std::string* error, bool* obstacle) {
    const GoalPlan r = planToGoal(*costmap_, footprint_, pose, goal_, s_.planner,
                                  s_.follower.omnidirectional ? 0.0 : s_.final_approach);
    if (!r.ok) {
      *error = r.error;
      *obstacle = r.blocked_by_obstacle;
      return false;
    }
    path_ = r.path;
    follower_.setPath(path_, goal_);
    publishPlan();
    ++plans_;
    return true;
  }

  void publishPlan() {
    nav_msgs::Path msg;
    msg.header.stamp = ros::Time::now();
    msg.header.frame_id = s_.global_frame;
    for (std::size_t i = 0; i < path_.size(); ++i) {
      geometry_msgs::PoseStamped p;
      p.header = msg.header;
      const Eigen::Vector2d d = i + 1 < path_.size() ? Eigen::Vector2d(path_[i + 1] - path_[i]) : Eigen::Vector2d(0, 0);
      p.pose = thorvald_map::toPose(
          {path_[i].x(), path_[i].y(), i + 1 < path_.size() ? std::atan2(d.y(), d.x()) : goal_.yaw});
      msg.poses.push_back(p);
    }
    plan_pub_.publish(msg);
  }

  // Is a lidar obstacle (not a known wall or the keep-out zone) under the footprint along the next
  // obstacle_check_ahead metres of the path?
  bool obstacleAhead(const thorvald_base::Pose2D& pose) const {
    return sweptObstacleDistance(*costmap_, footprint_, pose, path_, follower_.progressIndex() + 1,
                                 s_.obstacle_check_ahead, s_.follower.omnidirectional, goal_.yaw,
                                 follower_.reversing()) >= 0.0;
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
    thorvald_base::Pose2D pose;
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
      bool obstacle = false;
      if (!plan(pose, &error, &obstacle)) {
        // A goal blocked by the map or keep-out is refused at once; one blocked by lidar obstacles waits.
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
    const thorvald_base::Twist2D t = follower_.step(pose, dt);
    if (follower_.phase() != last_phase_) {
      last_phase_ = follower_.phase();
      ROS_INFO("headland_navigator: %.2f s into the goal: %s%s at (%.3f, %.3f, %.3f), %.3f m from the goal",
               (now - started_).toSec(), followPhaseName(last_phase_), follower_.reversing() ? " (reversing)" : "",
               pose.x, pose.y, pose.yaw, std::hypot(pose.x - goal_.x, pose.y - goal_.y));
    }
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
      const ArrivalJudgement j = arrival_.judge(pose, goal_);
      if (j.verdict == ArrivalVerdict::kApproachAgain && j.xy_err_m <= s_.follower.xy_tolerance_m) {
        // Only the heading is off: turn again where the robot stands (backing off would cost the position).
        ROS_INFO("headland_navigator: settled %.3f m, %.3f rad off the goal: turning again (%d of %d)", j.xy_err_m,
                 j.yaw_err_rad, arrival_.corrections(), s_.goal_corrections);
        follower_.turnTo(goal_);
        to_pre_goal_ = false;
        return;
      }
      if (j.verdict == ArrivalVerdict::kApproachAgain) {
        const Approach a =
            approachAgain(*costmap_, footprint_, pose, goal_, s_.final_approach, s_.follower.omnidirectional);
        ROS_INFO("headland_navigator: settled %.3f m, %.3f rad off the goal: approaching again%s (%d of %d)",
                 j.xy_err_m, j.yaw_err_rad, a.reverse ? ", backing off first" : "", arrival_.corrections(),
                 s_.goal_corrections);
        path_ = a.first_leg;
        follower_.setPath(path_, a.first_target, a.reverse);
        to_pre_goal_ = a.then_to_goal;
        pre_goal_ = Eigen::Vector2d(a.first_target.x, a.first_target.y);
        return;
      }
      active_ = false;
      if (j.verdict == ArrivalVerdict::kFailed) {
        abort(j.reason);
        return;
      }
      ROS_INFO("headland_navigator: goal reached (%.3f m, %.3f rad off, %d corrections) after %.1f s", j.xy_err_m,
               j.yaw_err_rad, arrival_.corrections(), (now - started_).toSec());
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
    fb.base_position.pose = thorvald_map::toPose(pose);
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
  ArrivalJudge arrival_;
  LocalizationGate gate_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  FrameLookup frames_;
  diagnostic_updater::Updater updater_;
  ActionServer server_;
  ros::Publisher cmd_pub_, plan_pub_, costmap_pub_, simple_client_pub_;
  ros::Subscriber map_sub_, keep_out_sub_, scan_sub_, simple_goal_sub_, status_sub_;
  ros::Timer timer_;
  thorvald_map::OccupancyGrid map_, keep_out_;
  std::unique_ptr<Costmap> costmap_;
  std::vector<Eigen::Vector2d> obstacles_, path_;
  thorvald_base::Pose2D goal_;
  bool active_ = false, need_plan_ = false;
  ros::Time blocked_since_, started_, last_scan_, arrived_at_, last_obstacle_update_;
  bool to_pre_goal_ = false;  // a correction is on its way to the start of the final approach
  Eigen::Vector2d pre_goal_{0.0, 0.0};
  FollowPhase last_phase_ = FollowPhase::kIdle;
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
