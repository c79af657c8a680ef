#include <cmath>

#include <gtest/gtest.h>

#include "thorvald_base/angles.h"
#include "thorvald_base/pose2d.h"

using thorvald_base::kPi;
using thorvald_base::normalizeAngle;
using thorvald_base::Pose2D;

namespace {

// The one angle convention of the workspace: [-pi, pi).
TEST(Angles, WrapIntoMinusPiToPi) {
  EXPECT_DOUBLE_EQ(normalizeAngle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(normalizeAngle(-kPi), -kPi);  // the closed end stays
  EXPECT_DOUBLE_EQ(normalizeAngle(kPi), -kPi);   // the open end wraps
  EXPECT_NEAR(normalizeAngle(3 * kPi), -kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(-3 * kPi / 2), kPi / 2, 1e-12);
  EXPECT_NEAR(normalizeAngle(kPi - 1e-9), kPi - 1e-9, 1e-15);
  EXPECT_NEAR(normalizeAngle(2 * kPi + 0.25), 0.25, 1e-12);
  EXPECT_NEAR(normalizeAngle(-7 * kPi + 0.5), -kPi + 0.5, 1e-12);
  EXPECT_NEAR(thorvald_base::angleDiff(-3.0, 3.0), 2 * kPi - 6.0, 1e-12);  // the short way round
  EXPECT_TRUE(std::isnan(normalizeAngle(NAN)));
}

TEST(Pose2D, ComposesAndInvertsAsTransforms) {
  const Pose2D a(1.0, 2.0, 0.5), b(-0.3, 0.7, -2.0);
  const Pose2D ab = a * b;
  // b's origin seen from a's parent: a's position plus b's offset turned by a's heading.
  EXPECT_NEAR(ab.x, 1.0 + std::cos(0.5) * -0.3 - std::sin(0.5) * 0.7, 1e-12);
  EXPECT_NEAR(ab.y, 2.0 + std::sin(0.5) * -0.3 + std::cos(0.5) * 0.7, 1e-12);
  EXPECT_NEAR(ab.yaw, -1.5, 1e-12);
  const Pose2D identity = a * a.inverse();
  EXPECT_NEAR(identity.x, 0.0, 1e-12);
  EXPECT_NEAR(identity.y, 0.0, 1e-12);
  EXPECT_NEAR(identity.yaw, 0.0, 1e-12);
  const Eigen::Vector2d p(0.4, -1.1);
  EXPECT_TRUE((a * b).transformPoint(p).isApprox(a.transformPoint(b.transformPoint(p))));
  EXPECT_TRUE(a.inverse().transformPoint(a.transformPoint(p)).isApprox(p));
  const Pose2D c(0.2, -0.4, 2.5);
  const Pose2D left = (a * b) * c, right = a * (b * c);
  EXPECT_NEAR(left.x, right.x, 1e-12);
  EXPECT_NEAR(left.y, right.y, 1e-12);
  EXPECT_NEAR(left.yaw, right.yaw, 1e-12);
}

TEST(Pose2D, HeadingsOfResultsAreNormalised) {
  const Pose2D turn(0.0, 0.0, 3.0);
  EXPECT_NEAR((turn * turn).yaw, 6.0 - 2 * kPi, 1e-12);
  EXPECT_DOUBLE_EQ(Pose2D(0.0, 0.0, kPi).inverse().yaw, -kPi);
  EXPECT_TRUE(Pose2D(1.0, 0.0, 0.0).heading().isApprox(Eigen::Vector2d(1.0, 0.0)));
  EXPECT_TRUE(Pose2D(1.0, 2.0, kPi / 2).heading().isApprox(Eigen::Vector2d(0.0, 1.0)));
  EXPECT_EQ(Pose2D(1.0, 2.0, 0.0).position(), Eigen::Vector2d(1.0, 2.0));
  EXPECT_TRUE(Pose2D().finite());
  EXPECT_FALSE(Pose2D(0.0, NAN, 0.0).finite());
}

}  // namespace
