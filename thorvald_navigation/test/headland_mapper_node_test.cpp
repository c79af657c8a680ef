// Starts headland_mapper (headland_mapper.test), drives a scripted robot along a synthetic headland and checks the
// published map and the map saved on ~save_map against the headland's walls.
#include <algorithm>
#include <cmath>
#include <vector>
#include <functional>

#include <gtest/gtest.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include "fake_headland_robot.h"
#include "thorvald_map/map_file.h"

namespace tn = thorvald_navigation;

namespace {

TEST(HeadlandMapperNode, MapsTheHeadlandAndSavesItOnRequest) {
  ros::NodeHandle nh;
  tn::testing::HeadlandOptions o;
  o.seed = 4;
  o.clutter_boxes = 1;
  const thorvald_base::Pose2D start{1.5, o.depth_m - 0.7, 0.0};
  tn::testing::FakeHeadlandRobot robot(nh, o, start, "odom");
  robot.setPublishedOffset(start.inverse());
  int maps = 0;
  ros::Subscriber sub =
      nh.subscribe<nav_msgs::OccupancyGrid>("map", 1, [&](const nav_msgs::OccupancyGrid::ConstPtr&) { ++maps; });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  thorvald_base::Pose2D truth = start;
  while (ros::ok() && truth.x < 8.0 && ros::WallTime::now() < deadline) {
    truth = truth * thorvald_base::Pose2D{0.6 * 0.025, 0.0, 0.0};
    robot.setTruth(truth);
    robot.step(0.025, false);
    ros::WallDuration(0.025).sleep();  // 40 Hz scans
  }
  for (int i = 0; i < 100 && maps == 0; ++i) {
    robot.step(0.025, false);
    ros::WallDuration(0.05).sleep();
  }
  EXPECT_GT(maps, 0);
  ros::ServiceClient save = nh.serviceClient<std_srvs::Trigger>("headland_mapper/save_map");
  ASSERT_TRUE(save.waitForExistence(ros::Duration(10.0)));
  std_srvs::Trigger srv;
  ASSERT_TRUE(save.call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  std::string stem;
  ASSERT_TRUE(ros::param::get("headland_mapper/map_file", stem));
  thorvald_map::OccupancyGrid saved;
  std::string error;
  ASSERT_TRUE(thorvald_map::loadMap(stem + ".yaml", &saved, &error)) << error;
  // Every wall cell of the saved map lies on a true wall (map frame = where mapping started). Distances are
  // measured to the wall segments themselves, not to a rasterised copy (that would round them to 5 cm steps).
  const auto& walls_true = robot.world().segments();
  auto wall_distance = [&](const Eigen::Vector2d& p) {
    double best = 1e9;
    for (const auto& s : walls_true) {
      const Eigen::Vector2d ab = s.b - s.a;
      const double t = std::clamp((p - s.a).dot(ab) / std::max(ab.squaredNorm(), 1e-12), 0.0, 1.0);
      best = std::min(best, (s.a + t * ab - p).norm());
    }
    return best;
  };
  int walls = 0, off = 0;
  std::vector<double> dist;
  for (int y = 0; y < saved.height; ++y)
    for (int x = 0; x < saved.width; ++x)
      if (saved.at(x, y) == thorvald_map::kOccupied) {
        ++walls;
        const double d = wall_distance(start.transformPoint(saved.cellCentre(x, y)));
        dist.push_back(d);
        off += d > 0.1;
      }
  EXPECT_GT(walls, 200);
  ASSERT_FALSE(dist.empty());
  std::nth_element(dist.begin(), dist.begin() + dist.size() / 2, dist.end());
  // A 5 cm cell that a wall crosses has its centre up to 3.5 cm from the wall; half the cells lie closer than that.
  EXPECT_LT(dist[dist.size() / 2], 0.035);
  EXPECT_LT(off, walls / 20);  // stray cells (grazing beams at long range) under 5 %
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "headland_mapper_node_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
