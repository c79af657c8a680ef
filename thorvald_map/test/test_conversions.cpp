#include <cmath>

#include <gtest/gtest.h>

#include "thorvald_map/ros/conversions.h"

namespace {

TEST(Conversions, PoseAndTransformRoundTrip) {
  for (const double yaw : {0.0, 0.4, -2.9, M_PI / 2}) {
    const thorvald_base::Pose2D p(1.5, -0.25, yaw);
    const thorvald_base::Pose2D a = thorvald_map::fromPose(thorvald_map::toPose(p));
    const thorvald_base::Pose2D b = thorvald_map::fromTransform(thorvald_map::toTransform(p));
    for (const auto& q : {a, b}) {
      EXPECT_DOUBLE_EQ(q.x, 1.5);
      EXPECT_DOUBLE_EQ(q.y, -0.25);
      EXPECT_NEAR(thorvald_base::angleDiff(q.yaw, yaw), 0.0, 1e-12) << yaw;
    }
  }
  const geometry_msgs::Pose identity = thorvald_map::toPose(thorvald_base::Pose2D());
  EXPECT_EQ(identity.orientation.w, 1.0);
  geometry_msgs::Pose unnormalised;
  unnormalised.orientation.z = 2.0 * std::sin(0.25);
  unnormalised.orientation.w = 2.0 * std::cos(0.25);
  EXPECT_NEAR(thorvald_map::fromPose(unnormalised).yaw, 0.5, 1e-12);
  EXPECT_FALSE(thorvald_map::fromPose(geometry_msgs::Pose()).finite());  // an all-zero quaternion has no heading
}

TEST(Conversions, GridRoundTripAndMalformedMessages) {
  thorvald_map::OccupancyGrid g(3, 2, 0.05, thorvald_base::Pose2D(-1.0, 2.0, 0.2), thorvald_map::kFree);
  g.at(2, 1) = thorvald_map::kOccupied;
  g.at(0, 1) = 42;
  const nav_msgs::OccupancyGrid msg = thorvald_map::toGridMessage(g, "map", ros::Time(5.0));
  EXPECT_EQ(msg.header.frame_id, "map");
  EXPECT_EQ(msg.info.map_load_time, ros::Time(5.0));
  EXPECT_EQ(msg.data[5], 100);
  thorvald_map::OccupancyGrid back;
  std::string error;
  ASSERT_TRUE(thorvald_map::fromGridMessage(msg, &back, &error)) << error;
  EXPECT_EQ(back.data, g.data);
  EXPECT_EQ(back.width, 3);
  EXPECT_NEAR(back.resolution_m, 0.05, 1e-7);  // a float in the message
  EXPECT_NEAR(back.origin.yaw, 0.2, 1e-12);
  EXPECT_FALSE(thorvald_map::fromGridMessage(msg, &back, &error, true));  // rotated, where that is refused
  EXPECT_NE(error.find("rotated"), std::string::npos) << error;

  nav_msgs::OccupancyGrid bad = msg;
  bad.data.resize(5);
  EXPECT_FALSE(thorvald_map::fromGridMessage(bad, &back, &error));
  EXPECT_NE(error.find("!= data size 5"), std::string::npos) << error;
  bad = msg;
  bad.info.resolution = 0.0f;
  EXPECT_FALSE(thorvald_map::fromGridMessage(bad, &back, &error));
  EXPECT_NE(error.find("resolution"), std::string::npos) << error;
  bad = msg;
  bad.info.origin.orientation = geometry_msgs::Quaternion();
  EXPECT_FALSE(thorvald_map::fromGridMessage(bad, &back, &error));
  EXPECT_NE(error.find("origin"), std::string::npos) << error;
  bad = nav_msgs::OccupancyGrid();
  EXPECT_FALSE(thorvald_map::fromGridMessage(bad, &back, &error));
  EXPECT_NE(error.find("empty"), std::string::npos) << error;
  // Round-off of an unrotated origin's quaternion is taken as no rotation.
  g.origin.yaw = 1e-9;
  ASSERT_TRUE(thorvald_map::fromGridMessage(thorvald_map::toGridMessage(g, "map"), &back, &error, true)) << error;
  EXPECT_EQ(back.origin.yaw, 0.0);
}

}  // namespace
