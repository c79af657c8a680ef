// Starts map_localizer (map_localizer.test) with a synthetic headland map and scripted scans: it must track the
// robot from an initial pose guess, report lost after a kidnapping, and recover by global_localization.
#include <cmath>
#include <functional>
#include <mutex>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <thorvald_common/ros/wait_for.h>
#include <std_msgs/String.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "fake_headland_robot.h"
#include "../src/nodes/ros_conversions.h"

namespace tn = thorvald_navigation;

namespace {

class LocalizerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tn::testing::HeadlandOptions o;
    o.seed = 3;
    // The robot's odometry frame starts where it stands: odom -> base_link is the motion since then.
    robot_ = std::make_unique<tn::testing::FakeHeadlandRobot>(nh_, o, start_, "odom");
    robot_->setPublishedOffset(start_.inverse());
    map_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
    initial_pub_ = nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("initialpose", 1, true);
    pose_sub_ = nh_.subscribe<geometry_msgs::PoseWithCovarianceStamped>(
        "amcl_pose", 5, [this](const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& m) {
          std::lock_guard<std::mutex> l(mutex_);
          pose_ = thorvald_map::fromPose(m->pose.pose);
          ++poses_;
        });
    status_sub_ =
        nh_.subscribe<std_msgs::String>("map_localizer/status", 5, [this](const std_msgs::String::ConstPtr& m) {
          std::lock_guard<std::mutex> l(mutex_);
          status_ = m->data;
        });
    map_pub_.publish(tn::testing::gridMessage(robot_->world().truthMap(0.05), "map"));
  }

  bool runUntil(const std::function<bool()>& done, double timeout_s) {
    return thorvald_common::waitFor(done, timeout_s, [this] {
      robot_->step(0.025);
      ros::WallDuration(0.025).sleep();  // 40 Hz scans, as the greenhouse lidar
    });
  }

  double error() {
    std::lock_guard<std::mutex> l(mutex_);
    const thorvald_base::Pose2D t = robot_->truth();
    return std::hypot(pose_.x - t.x, pose_.y - t.y) + std::abs(thorvald_base::normalizeAngle(pose_.yaw - t.yaw));
  }
  std::string status() {
    std::lock_guard<std::mutex> l(mutex_);
    return status_;
  }

  const thorvald_base::Pose2D start_{4.0, 2.2, 0.3};
  ros::NodeHandle nh_;
  std::unique_ptr<tn::testing::FakeHeadlandRobot> robot_;
  ros::Publisher map_pub_, initial_pub_;
  ros::Subscriber pose_sub_, status_sub_;
  std::mutex mutex_;
  thorvald_base::Pose2D pose_;
  int poses_ = 0;
  std::string status_;
};

TEST_F(LocalizerTest, RoughInitialPoseThenKidnappedRobotRecoveredByGlobalLocalization) {
  geometry_msgs::PoseWithCovarianceStamped guess;
  guess.header.frame_id = "map";
  guess.pose.pose = thorvald_map::toPose({start_.x + 0.3, start_.y - 0.2, start_.yaw + 0.15});  // a click in RViz
  ASSERT_TRUE(runUntil([this] { return initial_pub_.getNumSubscribers() > 0; }, 20.0));
  initial_pub_.publish(guess);
  ASSERT_TRUE(runUntil([this] { return status() == "localized" && error() < 0.05; }, 20.0)) << "error " << error();
  // tf carries the same answer: map -> base_link.
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  ASSERT_TRUE(runUntil([&] { return buffer.canTransform("map", "base_link", ros::Time(0)); }, 5.0));
  const thorvald_base::Pose2D via_tf =
      thorvald_map::fromTransform(buffer.lookupTransform("map", "base_link", ros::Time(0)).transform);
  EXPECT_LT(std::hypot(via_tf.x - start_.x, via_tf.y - start_.y), 0.05);

  // Kidnapped: carried elsewhere without odometry noticing.
  const thorvald_base::Pose2D elsewhere{11.0, 3.0, 2.5};
  robot_->setTruth(elsewhere);
  robot_->setPublishedOffset(elsewhere.inverse());  // odom -> base_link stays where it was
  ASSERT_TRUE(runUntil([this] { return status() == "lost"; }, 20.0)) << status();
  ros::ServiceClient global = nh_.serviceClient<std_srvs::Empty>("global_localization");
  std_srvs::Empty srv;
  ASSERT_TRUE(global.call(srv));
  ASSERT_TRUE(runUntil([this] { return status() == "localized" && error() < 0.05; }, 30.0))
      << "status " << status() << " error " << error();
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "map_localizer_node_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
