#pragma once

// Fake perception, manipulator and rover topics for the TopicHarvestPlant tests.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <geometry_msgs/PointStamped.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Float64.h>

#include "../cloud_message.h"
#include "cotton_harvester/BollArray.h"

namespace cotton_harvester {
namespace control {
namespace fake {

/// A manipulator that goes to each target at once and reports it (joint states at 50 Hz of wall time), a
/// perception that publishes what the test gives it, and a rover standing at 0 (reporting its position from the
/// start, or from reportRoverPosition(true) on).
class FakeRover {
 public:
  explicit FakeRover(const std::string& ns, bool rover_position = true) : nh_(ns), rover_position_(rover_position) {
    bolls_pub_ = nh_.advertise<cotton_harvester::BollArray>("bolls", 2);
    effector_pub_ = nh_.advertise<geometry_msgs::PointStamped>("end_effector/position", 5);
    joints_pub_ = nh_.advertise<sensor_msgs::JointState>("manipulator/joint_states", 5);
    busy_pub_ = nh_.advertise<std_msgs::Bool>("manipulator/busy", 5);
    rover_pub_ = nh_.advertise<std_msgs::Float64>("rover/position", 5);
    cloud_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("camera/depth/points", 4);
    target_sub_ = nh_.subscribe("manipulator/target", 5, &FakeRover::onTarget, this);
    brush_sub_ = nh_.subscribe("manipulator/brush", 5, &FakeRover::onBrush, this);
    timer_ = nh_.createWallTimer(ros::WallDuration(0.02), [this](const ros::WallTimerEvent&) { publishState(); });
  }

  bool connected() const {
    return bolls_pub_.getNumSubscribers() > 0 && effector_pub_.getNumSubscribers() > 0 &&
           joints_pub_.getNumSubscribers() > 0 && busy_pub_.getNumSubscribers() > 0 &&
           target_sub_.getNumPublishers() > 0 && brush_sub_.getNumPublishers() > 0;
  }

  void reportRoverPosition(bool on) { rover_position_ = on; }

  void publishFrame(const ros::Time& stamp, bool with_effector, double ee_x = 0.0, double ee_z = 0.0) {
    cotton_harvester::BollArray bolls;
    bolls.header.stamp = stamp;
    cotton_harvester::Boll b;
    b.position.x = -0.2;
    b.position.y = 0.01;
    b.position.z = 1.5;
    b.confidence = 0.9f;
    b.reachable = true;
    bolls.bolls.push_back(b);
    bolls_pub_.publish(bolls);
    if (with_effector) publishEffector(stamp, ee_x, ee_z);
  }

  void publishEffector(const ros::Time& stamp, double x, double z) {
    geometry_msgs::PointStamped p;
    p.header.stamp = stamp;
    p.point.x = x;
    p.point.y = 0.0;
    p.point.z = z;
    effector_pub_.publish(p);
  }

  /// An organised cloud (w x h, focal length f) of the ground at 2.2 m and, when `leaf`, a 12 x 10 cm leaf 1.55 m
  /// below the camera at x -0.30..-0.18 in the arm's plane (y 0.02), published with `stamp`.
  void publishCloud(const ros::Time& stamp, bool leaf) {
    const int w = 320, h = 180;
    const double f = 175.0, cx = 160.0, cy = 90.0;
    cv::Mat points(h, w, CV_32FC3);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const double rx = (u - cx) / f, ry = (v - cy) / f;
        double z = 2.2;
        if (leaf && rx * 1.55 >= -0.30 && rx * 1.55 <= -0.18 && std::abs(ry * 1.55 - 0.02) <= 0.05) z = 1.55;
        points.at<cv::Vec3f>(v, u) =
            cv::Vec3f(static_cast<float>(rx * z), static_cast<float>(ry * z), static_cast<float>(z));
      }
    std_msgs::Header header;
    header.stamp = stamp;
    cloud_pub_.publish(cotton_harvester::test::toCloud(points, header));
  }

  /// Every arm target received: (extension, depth), NaN for an axis left where it is.
  std::vector<std::pair<double, double>> targets() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return targets_;
  }

  /// The arm's extension each time the brush was switched (true: on).
  std::vector<std::pair<bool, double>> brushEvents() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return brush_events_;
  }
  double extension() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return extension_;
  }
  double depth() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return depth_;
  }

 private:
  void onTarget(const geometry_msgs::PointStamped::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    targets_.emplace_back(msg->point.x, msg->point.z);
    if (std::isfinite(msg->point.x)) target_extension_ = msg->point.x;
    if (std::isfinite(msg->point.z)) target_depth_ = msg->point.z;
  }
  void onBrush(const std_msgs::Bool::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    brush_events_.emplace_back(msg->data, extension_);
  }
  void publishState() {
    sensor_msgs::JointState joints;
    joints.header.stamp = ros::Time::now();
    joints.name = {"horizontal", "vertical"};
    bool moving = false;
    {
      // The axes move 1 cm per tick towards their targets, so a move of several centimetres takes several ticks.
      std::lock_guard<std::mutex> lock(mutex_);
      extension_ += std::clamp(target_extension_ - extension_, -kStep, kStep);
      depth_ += std::clamp(target_depth_ - depth_, -kStep, kStep);
      moving = extension_ != target_extension_ || depth_ != target_depth_;
      joints.position = {extension_, depth_};
    }
    joints_pub_.publish(joints);
    std_msgs::Bool busy;
    busy.data = moving;
    busy_pub_.publish(busy);
    if (!rover_position_) return;
    std_msgs::Float64 rover;
    rover.data = 0.0;
    rover_pub_.publish(rover);
  }

  ros::NodeHandle nh_;
  ros::Publisher bolls_pub_, effector_pub_, joints_pub_, busy_pub_, rover_pub_, cloud_pub_;
  ros::Subscriber target_sub_, brush_sub_;
  ros::WallTimer timer_;
  std::atomic<bool> rover_position_;
  mutable std::mutex mutex_;
  static constexpr double kStep = 0.01;
  double extension_ = 0.35, depth_ = 1.2, target_extension_ = 0.35, target_depth_ = 1.2;
  std::vector<std::pair<bool, double>> brush_events_;
  std::vector<std::pair<double, double>> targets_;
};

/// Frames (bolls, the end effector where the arm is, the cloud) at 20 Hz of wall time while it lives.
class FrameStream {
 public:
  FrameStream(FakeRover& fake, bool leaf) : fake_(fake), leaf_(leaf), thread_([this] { loop(); }) {}
  ~FrameStream() {
    stop_ = true;
    thread_.join();
  }

 private:
  void loop() {
    while (!stop_ && ros::ok()) {
      const ros::Time stamp = ros::Time::now();
      fake_.publishCloud(stamp, leaf_);
      fake_.publishFrame(stamp, true, fake_.extension() - 0.55, fake_.depth());
      ros::WallDuration(0.05).sleep();
    }
  }
  FakeRover& fake_;
  const bool leaf_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace fake
}  // namespace control
}  // namespace cotton_harvester
