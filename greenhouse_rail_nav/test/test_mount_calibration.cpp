#include <cmath>
#include <cstdio>

#include <unistd.h>

#include <gtest/gtest.h>

#include "greenhouse_rail_nav/mount_calibration.h"

using namespace greenhouse_rail_nav;

TEST(MountCalibration, CorrectionMakesTheRailsStraightAhead) {
  // Rails seen 4 cm to the left and turned 0.05 rad, origin (first visible point) 0.6 m ahead.
  const thorvald_base::Pose2D seen(0.6, 0.04, 0.05);
  MountCorrection c;
  std::string error;
  ASSERT_TRUE(computeMountCorrection(seen, 0.1, 0.1, &c, &error)) << error;
  const thorvald_base::Pose2D corrected = c.asTransform() * seen;
  EXPECT_NEAR(corrected.yaw, 0.0, 1e-12);
  EXPECT_NEAR(corrected.y, 0.0, 1e-12);
  // Any other point on the seen centre line also lands on y = 0.
  const Eigen::Vector2d far = seen.transformPoint({2.0, 0.0});
  EXPECT_NEAR(c.asTransform().transformPoint(far).y(), 0.0, 1e-12);
  EXPECT_NEAR(c.yaw_rad, -0.05, 1e-12);
}

TEST(MountCalibration, RefusesWhenTheRobotCannotBeOnTheRails) {
  MountCorrection c;
  std::string error;
  EXPECT_FALSE(computeMountCorrection(thorvald_base::Pose2D(0.6, 0.3, 0.0), 0.1, 0.1, &c, &error));
  EXPECT_NE(error.find("beyond the limits"), std::string::npos);
  EXPECT_FALSE(computeMountCorrection(thorvald_base::Pose2D(0.6, 0.0, 0.3), 0.1, 0.1, &c, &error));
  EXPECT_FALSE(computeMountCorrection(thorvald_base::Pose2D(NAN, 0.0, 0.0), 0.1, 0.1, &c, &error));
}

TEST(MountCalibration, PersistsToAFile) {
  const std::string path = ::testing::TempDir() + "/mount_" + std::to_string(::getpid()) + ".yaml";
  MountCorrection c{0.0123, -0.0456}, loaded;
  std::string error;
  ASSERT_TRUE(saveMountCorrection(c, path, &error)) << error;
  ASSERT_TRUE(loadMountCorrection(path, &loaded, &error)) << error;
  EXPECT_NEAR(loaded.y_m, 0.0123, 1e-9);
  EXPECT_NEAR(loaded.yaw_rad, -0.0456, 1e-9);
  std::remove(path.c_str());
  EXPECT_FALSE(loadMountCorrection(path, &loaded, &error));
  EXPECT_NE(error.find(path), std::string::npos);
}
