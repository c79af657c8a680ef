// headland_navigator: move_base's interface (move_base_msgs/MoveBaseAction on `move_base`,
// `move_base_simple/goal`) over a global A* plan on the map plus the keep-out grid, inflated for the robot's
// footprint, and a path follower (omnidirectional where every drive steers, differential otherwise) that stops for
// lidar obstacles and replans. Commands go to `nav_vel`. ROS I/O only: the goal's lifecycle is GoalRunner's (on the
// Costmap through costmapPlanners), this node converts messages, keeps the costmap's layers, publishes what the
// runner decides and reports diagnostics; parameters in headland_navigator_settings.
#include <algorithm>
#include <cmath>
#include <memory>
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
#include "thorvald_navigation/goal_runner.h"
#include "thorvald_navigation/localization_gate.h"

namespace thorvald_navigation {
namespace {

using ActionServer = actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>;

class HeadlandNavigatorNode {
 public:
  HeadlandNavigatorNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const Settings& s)
      : s_(s),
        footprint_(makeFootprint(s.footprint, s.footprint_padding)),
        runner_(s.goal, costmapPlanners([this]() -> const Costmap& { return *costmap_; }, footprint_, s.planner,
                                        s.final_approach, s.obstacle_check_ahead, s.goal.follower.omnidirectional)),
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
    // Re-inflating around what a scan changed costs little, but not for every scan of a 40 Hz lidar.
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
    if (state != runner_.localizerState())
      ROS_INFO_STREAM("headland_navigator: localiser " << localizerStateName(state));
    runner_.setLocalizerStatus(state, ros::Time::now().toSec());
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
        apply(runner_.abort("goal frame '" + frame + "' cannot be transformed to '" + s_.global_frame + "': " + error));
        return;
      }
      g = frame_in_map * g;
    }
    apply(runner_.accept(g, ros::Time::now().toSec()));
  }

  void onPreempt() { apply(runner_.cancel()); }

  // Sends what the goal runner decided: its log lines, the plan, the command to the base, the goal's result.
  // `pose` and `stamp`: the cycle's, for the feedback.
  void apply(const GoalTick& t, const thorvald_base::Pose2D* pose = nullptr, const ros::Time& stamp = ros::Time()) {
    for (const GoalNote& n : t.notes) {
      if (n.warning)
        ROS_WARN_STREAM("headland_navigator: " << n.text);
      else
        ROS_INFO_STREAM("headland_navigator: " << n.text);
    }
    if (t.new_plan) publishPlan();
    if (t.command == DriveCommand::kStop) cmd_pub_.publish(geometry_msgs::Twist());
    if (t.command == DriveCommand::kTwist) {
      geometry_msgs::Twist cmd;
      cmd.linear.x = t.twist.vx;
      cmd.linear.y = t.twist.vy;
      cmd.angular.z = t.twist.wz;
      cmd_pub_.publish(cmd);
      if (pose) publishFeedback(*pose, stamp);
    }
    if (t.state == GoalState::kAborted && server_.isActive())
      server_.setAborted(move_base_msgs::MoveBaseResult(), t.reason);
    if (t.state == GoalState::kSucceeded) server_.setSucceeded(move_base_msgs::MoveBaseResult(), "goal reached");
    if (t.state == GoalState::kCancelled) server_.setPreempted(move_base_msgs::MoveBaseResult(), "cancelled");
  }

  void publishFeedback(const thorvald_base::Pose2D& pose, const ros::Time& stamp) {
    move_base_msgs::MoveBaseFeedback fb;
    fb.base_position.header.stamp = stamp;
    fb.base_position.header.frame_id = s_.global_frame;
    fb.base_position.pose = thorvald_map::toPose(pose);
    server_.publishFeedback(fb);
  }

  void publishPlan() {
    const std::vector<Eigen::Vector2d>& path = runner_.path();
    const thorvald_base::Pose2D& goal = runner_.goal();
    nav_msgs::Path msg;
    msg.header.stamp = ros::Time::now();
    msg.header.frame_id = s_.global_frame;
    for (std::size_t i = 0; i < path.size(); ++i) {
      geometry_msgs::PoseStamped p;
      p.header = msg.header;
      const Eigen::Vector2d d = i + 1 < path.size() ? Eigen::Vector2d(path[i + 1] - path[i]) : Eigen::Vector2d(0, 0);
      p.pose =
          thorvald_map::toPose({path[i].x(), path[i].y(), i + 1 < path.size() ? std::atan2(d.y(), d.x()) : goal.yaw});
      msg.poses.push_back(p);
    }
    plan_pub_.publish(msg);
  }

  // The lidar went quiet: do not steer around ghosts, but say so.
  void forgetStaleObstacles(const ros::Time& now) {
    if (last_scan_.isZero() || (now - last_scan_).toSec() <= s_.scan_max_age || obstacles_.empty()) return;
    obstacles_.clear();
    if (costmap_) costmap_->setObstacles(obstacles_);
    ROS_WARN_THROTTLE(5.0, "headland_navigator: no recent scan: obstacle layer cleared");
  }

  void onTimer(const ros::TimerEvent& ev) {
    updater_.update();
    if (!runner_.active()) return;
    if (!server_.isActive()) {
      runner_.drop();
      return;
    }
    const ros::Time now = ros::Time::now();
    forgetStaleObstacles(now);
    GoalRunnerInput in;
    in.now_s = now.toSec();
    in.dt_s =
        ev.last_real.isZero() ? 1.0 / s_.controller_frequency : std::min(0.5, (ev.current_real - ev.last_real).toSec());
    std::string error;
    thorvald_base::Pose2D pose;
    if (costmap_ && frames_.lookup(s_.global_frame, s_.base_frame, ros::Time(0), 0.0, &pose, &error))
      in.pose = pose;
    else
      in.no_pose_reason = costmap_ ? "no robot pose in " + s_.global_frame + ": " + error : "no map received on 'map'";
    apply(runner_.tick(in), in.pose ? &*in.pose : nullptr, now);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& st) {
    using D = diagnostic_msgs::DiagnosticStatus;
    if (!costmap_) {
      st.summary(D::WARN, "no map yet");
    } else if (runner_.active() && runner_.holding()) {
      st.summary(D::WARN, runner_.holdReason());
    } else if (runner_.active() && runner_.blocked()) {
      st.summary(D::WARN, "blocked by an obstacle");
    } else {
      st.summary(D::OK, runner_.active() ? "navigating" : "idle");
    }
    st.add("drive mode", s_.drive_mode);
    st.add("keep-out grid", keep_out_.width > 0 ? "received" : "none");
    const GoalRunnerCounts& n = runner_.counts();
    st.add("plans", n.plans);
    st.add("goals reached", n.reached);
    st.add("obstacle stops (cycles)", n.obstacle_stops);
    if (costmap_) {
      st.add("lidar points: obstacles", costmap_->obstaclePoints());
      st.add("lidar points: known walls / keep-out", costmap_->knownStructurePoints());
    }
    st.add("localiser status", localizerStateName(runner_.localizerState()));
    st.add("waits for relocalisation", n.relocalisation_waits);
    st.add("localiser statuses not understood", bad_statuses_);
    st.add("last failure", runner_.lastFailure());
  }

  Settings s_;
  Footprint footprint_;
  GoalRunner runner_;
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
  std::vector<Eigen::Vector2d> obstacles_;
  ros::Time last_scan_, last_obstacle_update_;
  long bad_statuses_ = 0;
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
