#pragma once

// A scripted robot for the node tests: a synthetic headland, a kinematic base that integrates `nav_vel`, and the
// lidar scans and transforms a real robot would publish. The tests step it from their own thread.
#include <cmath>
#include <mutex>
#include <random>
#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include "thorvald_navigation/testing/synthetic_headland.h"

namespace thorvald_navigation {
namespace testing {

inline geometry_msgs::TransformStamped makeTransform(const std::string& parent, const std::string& child,
                                                     const thorvald_base::Pose2D& p, const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation.x = p.x;
  t.transform.translation.y = p.y;
  tf2::Quaternion q;
  q.setRPY(0, 0, p.yaw);
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  return t;
}

inline nav_msgs::OccupancyGrid gridMessage(const thorvald_map::OccupancyGrid& g, const std::string& frame) {
  nav_msgs::OccupancyGrid m;
  m.header.frame_id = frame;
  m.header.stamp = ros::Time::now();
  m.info.resolution = static_cast<float>(g.resolution_m);
  m.info.width = g.width;
  m.info.height = g.height;
  m.info.origin.position.x = g.origin.x;
  m.info.origin.position.y = g.origin.y;
  m.info.origin.orientation.w = 1.0;
  m.data.assign(g.data.begin(), g.data.end());
  return m;
}

class FakeHeadlandRobot {
 public:
  /// `parent_frame`: the frame the robot's pose is published in ("odom" or "map").
  FakeHeadlandRobot(ros::NodeHandle& nh, const HeadlandOptions& options, const thorvald_base::Pose2D& start,
                    const std::string& parent_frame)
      : world_(options), truth_(start), parent_(parent_frame), rng_(7) {
    scan_pub_ = nh.advertise<sensor_msgs::LaserScan>("scan", 5);
    cmd_sub_ = nh.subscribe("nav_vel", 5, &FakeHeadlandRobot::onCmd, this);
    static_tf_.sendTransform(makeTransform("base_link", "laser", {0.45, 0.0, 0.0}, ros::Time::now()));
  }

  SyntheticHeadland& world() { return world_; }
  thorvald_base::Pose2D truth() {
    std::lock_guard<std::mutex> l(mutex_);
    return truth_;
  }
  void setTruth(const thorvald_base::Pose2D& p) {
    std::lock_guard<std::mutex> l(mutex_);
    truth_ = p;
  }
  /// Pose published on tf (parent -> base_link): truth unless `published` was overridden (kidnapping).
  void setPublishedOffset(const thorvald_base::Pose2D& offset) { offset_ = offset; }
  geometry_msgs::Twist lastCommand() {
    std::lock_guard<std::mutex> l(mutex_);
    return cmd_;
  }
  /// Zero commands received so far.
  int stops() {
    std::lock_guard<std::mutex> l(mutex_);
    return stops_;
  }
  ros::Time lastCommandTime() {
    std::lock_guard<std::mutex> l(mutex_);
    return cmd_time_;
  }

  /// Integrates the last command for dt [s] (zero after 0.5 s without one), publishes tf and a scan.
  void step(double dt, bool move = true) {
    const ros::Time now = ros::Time::now();
    thorvald_base::Pose2D pose;
    {
      std::lock_guard<std::mutex> l(mutex_);
      if (move && !cmd_time_.isZero() && (now - cmd_time_).toSec() < 0.5)
        truth_ = truth_ * thorvald_base::Pose2D{cmd_.linear.x * dt, cmd_.linear.y * dt, cmd_.angular.z * dt};
      pose = truth_;
    }
    tf_.sendTransform(makeTransform(parent_, "base_link", offset_ * pose, now));
    sensor_msgs::LaserScan s;
    s.header.stamp = now;
    s.header.frame_id = "laser";
    s.angle_min = -2.356f;
    s.angle_max = 2.356f;
    const int beams = 541;
    s.angle_increment = static_cast<float>((2.0 * 2.356) / (beams - 1));
    s.range_min = 0.1f;
    s.range_max = 30.0f;
    std::normal_distribution<double> noise(0.0, 0.01);
    const Eigen::Vector2d origin = pose.transformPoint({0.45, 0.0});
    for (int i = 0; i < beams; ++i) {
      const double a = s.angle_min + i * s.angle_increment;
      const double r = world_.castRay(origin, pose.yaw + a, 30.0);
      s.ranges.push_back(r >= 30.0 ? std::numeric_limits<float>::infinity() : static_cast<float>(r + noise(rng_)));
    }
    scan_pub_.publish(s);
  }

 private:
  void onCmd(const geometry_msgs::Twist::ConstPtr& msg) {
    std::lock_guard<std::mutex> l(mutex_);
    cmd_ = *msg;
    cmd_time_ = ros::Time::now();
    if (msg->linear.x == 0.0 && msg->linear.y == 0.0 && msg->angular.z == 0.0) ++stops_;
  }

  SyntheticHeadland world_;
  std::mutex mutex_;
  thorvald_base::Pose2D truth_;
  thorvald_base::Pose2D offset_;
  std::string parent_;
  std::mt19937 rng_;
  geometry_msgs::Twist cmd_;
  ros::Time cmd_time_;
  int stops_ = 0;
  ros::Publisher scan_pub_;
  ros::Subscriber cmd_sub_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
};

}  // namespace testing
}  // namespace thorvald_navigation
