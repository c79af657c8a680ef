// Starts headland_navigator (headland_navigator.test) against a scripted robot on a synthetic headland: the test
// publishes the map, the keep-out grid, map -> base_link and lidar scans, and executes nav_vel.
#include <atomic>
#include <cmath>
#include <functional>

#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>

#include "fake_headland_robot.h"

namespace tn = thorvald_navigation;
using Client = actionlib::SimpleActionClient<move_base_msgs::MoveBaseAction>;

namespace {

tn::testing::HeadlandOptions headland() {
  tn::testing::HeadlandOptions o;
  o.clutter_boxes = 0;
  o.length_m = 14.0;
  o.depth_m = 5.0;
  return o;
}

class NavigatorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    robot_ = std::make_unique<tn::testing::FakeHeadlandRobot>(nh_, headland(), tn::Pose2D{2.0, 2.5, 0.0}, "map");
    map_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
    keep_out_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("keep_out_map", 1, true);
    plan_sub_ = nh_.subscribe<nav_msgs::Path>("headland_navigator/plan", 10,
                                              [this](const nav_msgs::Path::ConstPtr&) { ++plans_; });
    const tn::Grid2D map = robot_->world().truthMap(0.05);
    map_pub_.publish(tn::testing::gridMessage(map, "map"));
    // The virtual wall: everything beyond 0.3 m before the rows' start (the headland edge) is out of bounds.
    tn::Grid2D keep_out(map.width, map.height, map.resolution_m, map.origin_x_m, map.origin_y_m, tn::kFree);
    for (int y = 0; y < map.height; ++y)
      for (int x = 0; x < map.width; ++x)
        if (map.centerOf(x, y).y() > headland().depth_m - 0.3) keep_out.at(x, y) = tn::kOccupied;
    keep_out_pub_.publish(tn::testing::gridMessage(keep_out, "map"));
    client_ = std::make_unique<Client>("move_base", false);
    ASSERT_TRUE(runUntil([this] { return client_->isServerConnected(); }, 20.0));
    robot_->step(0.05, false);
    ros::Duration(0.5).sleep();  // let the navigator receive the latched map and keep-out grid
  }

  // Steps the robot at 20 Hz until `done` or the deadline [s]; `each` runs every step.
  bool runUntil(const std::function<bool()>& done, double timeout_s, const std::function<void()>& each = {}) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::ok() && ros::WallTime::now() < end) {
      if (done()) return true;
      robot_->step(0.05);
      if (each) each();
      ros::WallDuration(0.05).sleep();  // paces the scripted robot at its control rate
    }
    return done();
  }

  move_base_msgs::MoveBaseGoal goal(double x, double y, double yaw) {
    move_base_msgs::MoveBaseGoal g;
    g.target_pose.header.frame_id = "map";
    g.target_pose.header.stamp = ros::Time::now();
    const auto t = tn::testing::makeTransform("map", "goal", {x, y, yaw}, ros::Time::now());
    g.target_pose.pose.position.x = x;
    g.target_pose.pose.position.y = y;
    g.target_pose.pose.orientation = t.transform.rotation;
    return g;
  }

  bool finished() { return client_->getState().isDone(); }

  ros::NodeHandle nh_;
  std::unique_ptr<tn::testing::FakeHeadlandRobot> robot_;
  std::unique_ptr<Client> client_;
  ros::Publisher map_pub_, keep_out_pub_;
  ros::Subscriber plan_sub_;
  std::atomic<int> plans_{0};
};

TEST_F(NavigatorTest, GoalBehindTheKeepOutLineIsRefusedWithTheReason) {
  client_->sendGoal(goal(6.0, 5.5, 1.57));
  ASSERT_TRUE(runUntil([this] { return finished(); }, 10.0));
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::ABORTED);
  EXPECT_NE(client_->getState().getText().find("keep-out"), std::string::npos) << client_->getState().getText();
}

TEST_F(NavigatorTest, ReachesAGoalWithinTolerance) {
  client_->sendGoal(goal(7.0, 3.2, 1.0));
  ASSERT_TRUE(runUntil([this] { return finished(); }, 60.0));
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::SUCCEEDED) << client_->getState().getText();
  const tn::Pose2D p = robot_->truth();
  EXPECT_LT(std::hypot(p.x - 7.0, p.y - 3.2), 0.03);
  EXPECT_LT(std::abs(tn::normalizeAngle(p.yaw - 1.0)), 0.03);
  EXPECT_GE(plans_.load(), 1);
}

TEST_F(NavigatorTest, AnObstacleStopsTheRobotAndItReplansAroundIt) {
  client_->sendGoal(goal(11.0, 2.5, 0.0));
  ASSERT_TRUE(runUntil([this] { return robot_->truth().x > 3.0; }, 30.0));
  const int plans_before = plans_.load();
  const Eigen::Vector2d box(6.0, 2.5);
  robot_->world().addBox(box, 0.5);  // a person steps onto the path
  const int stops_before = robot_->stops();
  double closest = 1e9;
  ASSERT_TRUE(runUntil([this] { return finished(); }, 90.0,
                       [&] {
                         const tn::Pose2D p = robot_->truth();
                         closest = std::min(closest, (Eigen::Vector2d(p.x, p.y) - box).norm());
                       }));
  // Zero commands: the stop for the obstacle, and the final one at the goal.
  const bool stopped = robot_->stops() >= stops_before + 2;
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::SUCCEEDED) << client_->getState().getText();
  EXPECT_TRUE(stopped);
  EXPECT_GT(plans_.load(), plans_before);
  EXPECT_GT(closest, 0.25 + 0.3);  // box half size + the robot's half width: never touched it
}

TEST_F(NavigatorTest, CancelStopsTheRobot) {
  client_->sendGoal(goal(11.0, 2.5, 0.0));
  ASSERT_TRUE(runUntil([this] { return robot_->truth().x > 2.8; }, 30.0));
  client_->cancelGoal();
  ASSERT_TRUE(runUntil([this] { return finished(); }, 5.0));
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::PREEMPTED);
  runUntil([] { return false; }, 0.5);
  const auto c = robot_->lastCommand();
  EXPECT_EQ(c.linear.x, 0.0);
  EXPECT_EQ(c.angular.z, 0.0);
  const double x = robot_->truth().x;
  runUntil([] { return false; }, 1.0);
  EXPECT_NEAR(robot_->truth().x, x, 1e-9);  // no command after the cancel
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "headland_navigator_node_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
