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
#include <thorvald_common/ros/wait_for.h>
#include <std_msgs/String.h>

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
    robot_ =
        std::make_unique<tn::testing::FakeHeadlandRobot>(nh_, headland(), thorvald_base::Pose2D{2.0, 2.5, 0.0}, "map");
    map_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
    keep_out_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("keep_out_map", 1, true);
    status_pub_ = nh_.advertise<std_msgs::String>("map_localizer/status", 1, true);
    setStatus("localized");  // each test starts localised (the status is latched across tests)
    plan_sub_ = nh_.subscribe<nav_msgs::Path>("headland_navigator/plan", 10,
                                              [this](const nav_msgs::Path::ConstPtr&) { ++plans_; });
    const thorvald_map::OccupancyGrid map = robot_->world().truthMap(0.05);
    map_pub_.publish(tn::testing::gridMessage(map, "map"));
    // The virtual wall: everything beyond 0.3 m before the rows' start (the headland edge) is out of bounds.
    thorvald_map::OccupancyGrid keep_out(map.width, map.height, map.resolution_m, map.origin.x, map.origin.y,
                                         thorvald_map::kFree);
    for (int y = 0; y < map.height; ++y)
      for (int x = 0; x < map.width; ++x)
        if (map.cellCentre(x, y).y() > headland().depth_m - 0.3) keep_out.at(x, y) = thorvald_map::kOccupied;
    keep_out_pub_.publish(tn::testing::gridMessage(keep_out, "map"));
    client_ = std::make_unique<Client>("move_base", false);
    ASSERT_TRUE(runUntil([this] { return client_->isServerConnected(); }, 20.0));
    robot_->step(0.05, false);
    ros::Duration(0.5).sleep();  // let the navigator receive the latched map and keep-out grid
  }

  // Steps the robot at 20 Hz until `done` or the deadline [s]; `each` runs every step.
  bool runUntil(const std::function<bool()>& done, double timeout_s, const std::function<void()>& each = {}) {
    return thorvald_common::waitFor(done, timeout_s, [&] {
      robot_->step(0.05);
      if (each) each();
      ros::WallDuration(0.05).sleep();  // paces the scripted robot at its control rate
    });
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

  void setStatus(const std::string& status) {
    std_msgs::String m;
    m.data = status;
    status_pub_.publish(m);
  }

  // Steps the robot for `seconds` and returns how far base_link moved [m].
  double movedDuring(double seconds) {
    const thorvald_base::Pose2D a = robot_->truth();
    runUntil([] { return false; }, seconds);
    const thorvald_base::Pose2D b = robot_->truth();
    return std::hypot(b.x - a.x, b.y - a.y) + std::abs(thorvald_base::normalizeAngle(b.yaw - a.yaw));
  }

  ros::NodeHandle nh_;
  std::unique_ptr<tn::testing::FakeHeadlandRobot> robot_;
  std::unique_ptr<Client> client_;
  ros::Publisher map_pub_, keep_out_pub_, status_pub_;
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
  const thorvald_base::Pose2D p = robot_->truth();
  EXPECT_LT(std::hypot(p.x - 7.0, p.y - 3.2), 0.03);
  EXPECT_LT(std::abs(thorvald_base::normalizeAngle(p.yaw - 1.0)), 0.03);
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
                         const thorvald_base::Pose2D p = robot_->truth();
                         closest = std::min(closest, (Eigen::Vector2d(p.x, p.y) - box).norm());
                       }));
  // Zero commands: the stop for the obstacle, and the final one at the goal.
  const bool stopped = robot_->stops() >= stops_before + 2;
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::SUCCEEDED) << client_->getState().getText();
  EXPECT_TRUE(stopped);
  EXPECT_GT(plans_.load(), plans_before);
  EXPECT_GT(closest, 0.25 + 0.3);  // box half size + the robot's half width: never touched it
}

// A goal behind the robot: it must turn half round on the spot, its rear (0.91 m behind base_link) sweeping a circle
// that holds a crate standing beside it, clear of its box now and of the straight drive afterwards. The navigator
// does not start the turn: the robot stays where it is, and the goal is aborted after obstacle_wait (10 s).
TEST_F(NavigatorTest, AnObstacleBesideTheRobotStopsATurnOnTheSpot) {
  const Eigen::Vector2d crate(2.2, 3.1);  // 0.2 m ahead of base_link, 0.6 m to its left
  robot_->world().addBox(crate, 0.1);
  runUntil([] { return false; }, 0.5);  // scans with the crate reach the navigator
  const thorvald_base::Pose2D before = robot_->truth();
  client_->sendGoal(goal(0.9, 2.5, thorvald_base::kPi));
  ASSERT_TRUE(runUntil([this] { return finished(); }, 30.0));
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::ABORTED) << client_->getState().getText();
  EXPECT_NE(client_->getState().getText().find("obstacle"), std::string::npos) << client_->getState().getText();
  const thorvald_base::Pose2D after = robot_->truth();
  EXPECT_LT(std::abs(thorvald_base::normalizeAngle(after.yaw - before.yaw)), 0.02) << "started the turn into the crate";
  EXPECT_LT(std::hypot(after.x - before.x, after.y - before.y), 0.02);
}

TEST_F(NavigatorTest, MappedWallBesideThePathDoesNotStopTheRobot) {
  // Along the headland's outer wall (y = 0) with the localiser 6 cm off towards the floor's middle: the lidar puts
  // the wall's face 6 cm inside the map's floor, under the robot's padded box, as a real localiser's error and the
  // map's cells do. That is the wall, which the plan already keeps clear of, not an obstacle to stop for.
  robot_->setTruth({2.0, 0.39, 0.0});
  robot_->setPublishedOffset({0.0, 0.06, 0.0});
  runUntil([] { return false; }, 0.5);
  client_->sendGoal(goal(8.0, 0.45, 0.0));
  ASSERT_TRUE(runUntil([this] { return finished(); }, 60.0));
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::SUCCEEDED) << client_->getState().getText();
  const thorvald_base::Pose2D p = robot_->truth();
  EXPECT_LT(std::hypot(p.x - 8.0, p.y - 0.39), 0.03);
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

// The localiser reports lost on the way (headland_navigator.test: localization_lost_wait 4 s): the robot stops where
// it is, stays stopped, and the goal is aborted with the reason when no relocalisation comes.
TEST_F(NavigatorTest, LostLocaliserStopsTheRobotAndTheGoalIsAbortedWithTheReason) {
  client_->sendGoal(goal(11.0, 2.5, 0.0));
  ASSERT_TRUE(runUntil([this] { return robot_->truth().x > 3.0; }, 30.0));
  setStatus("lost");
  const ros::WallTime lost_at = ros::WallTime::now();
  runUntil([] { return false; }, 0.5);  // the status arrives, the zero command is executed
  EXPECT_LT(movedDuring(2.0), 1e-6) << "drove on a pose the localiser called lost";
  EXPECT_FALSE(finished()) << "aborted before the wait: " << client_->getState().getText();
  ASSERT_TRUE(runUntil([this] { return finished(); }, 15.0));
  EXPECT_GE((ros::WallTime::now() - lost_at).toSec(), 3.5);
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::ABORTED);
  EXPECT_NE(client_->getState().getText().find("localiser lost"), std::string::npos) << client_->getState().getText();
  EXPECT_LT(movedDuring(0.5), 1e-6);
}

// Lost, then localised again before the wait is over: the robot replans from its pose and reaches the goal.
TEST_F(NavigatorTest, RelocalisedRobotGoesOnToTheGoal) {
  client_->sendGoal(goal(8.0, 3.0, 0.5));
  ASSERT_TRUE(runUntil([this] { return robot_->truth().x > 3.0; }, 30.0));
  const int plans_before = plans_.load();
  setStatus("lost");
  runUntil([] { return false; }, 0.5);
  EXPECT_LT(movedDuring(1.5), 1e-6);
  setStatus("uncertain");  // the re-check found it; the pose is used while the next scans confirm it
  ASSERT_TRUE(runUntil([this] { return robot_->truth().x > 4.0; }, 20.0)) << "did not drive on";
  EXPECT_GT(plans_.load(), plans_before);  // planned again from where the localiser put it
  // Arrived while still uncertain: the goal waits for a certain pose before it is judged.
  ASSERT_TRUE(runUntil([this] { return std::hypot(robot_->truth().x - 8.0, robot_->truth().y - 3.0) < 0.03; }, 60.0));
  runUntil([] { return false; }, 1.5);
  EXPECT_FALSE(finished()) << client_->getState().getText();
  setStatus("localized");
  ASSERT_TRUE(runUntil([this] { return finished(); }, 20.0));
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::SUCCEEDED) << client_->getState().getText();
}

// Unknown status texts are ignored (counted in the diagnostics), never taken for a loss or a fix.
TEST_F(NavigatorTest, UnknownStatusTextDoesNotStopTheRobot) {
  client_->sendGoal(goal(7.0, 2.5, 0.0));
  ASSERT_TRUE(runUntil([this] { return robot_->truth().x > 2.8; }, 30.0));
  setStatus("LOST!!");
  ASSERT_TRUE(runUntil([this] { return finished(); }, 60.0));
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::SUCCEEDED) << client_->getState().getText();
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "headland_navigator_node_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
