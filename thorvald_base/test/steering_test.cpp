#include <gtest/gtest.h>

#include <cmath>

#include "thorvald_base/angles.h"
#include "thorvald_base/steering_optimizer.h"

using thorvald_base::alignmentScale;
using thorvald_base::chooseSteering;
using thorvald_base::kPi;

namespace {
constexpr double kLim = 3.078027759;  // about 176 deg
constexpr double kDeg = kPi / 180.0;
}  // namespace

TEST(Steering, ForwardThenBackwardKeepsTheWheelStraight) {
  // Driving backwards wants 180 deg; the twin at 0 deg with reversed speed is reached at once.
  const auto c = chooseSteering(kPi, 0.0, kLim);
  EXPECT_NEAR(c.angle_rad, 0.0, 1e-12);
  EXPECT_EQ(c.speed_sign, -1.0);
  EXPECT_EQ(c.speed_factor, 1.0);
}

TEST(Steering, NearerTwinWins) {
  // Wheel at 80 deg wants -100 deg: the twin 80 deg is where it already is.
  auto c = chooseSteering(-100 * kDeg, 80 * kDeg, kLim);
  EXPECT_NEAR(c.angle_rad, 80 * kDeg, 1e-12);
  EXPECT_EQ(c.speed_sign, -1.0);
  // Wheel at -80 deg wants -100 deg: direct is nearer (20 deg) than the twin at 80 deg (160 deg).
  c = chooseSteering(-100 * kDeg, -80 * kDeg, kLim);
  EXPECT_NEAR(c.angle_rad, -100 * kDeg, 1e-12);
  EXPECT_EQ(c.speed_sign, 1.0);
}

TEST(Steering, StaysInsideTheCableLimit) {
  // 178 deg is beyond +-176 deg: only the twin at -2 deg is allowed, even from a wheel at 170 deg.
  const auto c = chooseSteering(178 * kDeg, 170 * kDeg, kLim);
  EXPECT_NEAR(c.angle_rad, -2 * kDeg, 1e-12);
  EXPECT_EQ(c.speed_sign, -1.0);
}

TEST(Steering, NoWrapThroughPi) {
  // From 170 deg to -170 deg is 20 deg across pi, but the cable forbids that path: the travel counts 340 deg,
  // so the twin at 10 deg (160 deg away) is chosen.
  const auto c = chooseSteering(-170 * kDeg, 170 * kDeg, kLim);
  EXPECT_NEAR(c.angle_rad, 10 * kDeg, 1e-12);
  EXPECT_EQ(c.speed_sign, -1.0);
}

TEST(Steering, NarrowLimitClampsAndReducesSpeed) {
  const double lim = 30 * kDeg;
  const auto c = chooseSteering(60 * kDeg, 0.0, lim);
  EXPECT_NEAR(c.angle_rad, lim, 1e-12);
  EXPECT_EQ(c.speed_sign, 1.0);
  EXPECT_NEAR(c.speed_factor, std::cos(30 * kDeg), 1e-12);
  // Wanting 150 deg: the twin -30 deg fits exactly.
  const auto t = chooseSteering(150 * kDeg, 0.0, lim);
  EXPECT_NEAR(t.angle_rad, -30 * kDeg, 1e-12);
  EXPECT_EQ(t.speed_sign, -1.0);
  EXPECT_NEAR(t.speed_factor, 1.0, 1e-12);
  // Sideways with a narrow limit: nothing of the motion fits.
  const auto s = chooseSteering(90 * kDeg, 0.0, lim);
  EXPECT_NEAR(s.speed_factor, std::cos(60 * kDeg), 1e-12);
}

TEST(Steering, AlignmentScale) {
  EXPECT_DOUBLE_EQ(alignmentScale(0.0, 0.1, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(alignmentScale(0.1, 0.1, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(alignmentScale(0.3, 0.1, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(alignmentScale(-0.3, 0.1, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(alignmentScale(0.5, 0.1, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(alignmentScale(2.0, 0.1, 0.5), 0.0);
}

TEST(Angles, Normalize) {
  EXPECT_NEAR(thorvald_base::normalizeAngle(3 * kPi), -kPi, 1e-12);
  EXPECT_NEAR(thorvald_base::normalizeAngle(-0.5), -0.5, 1e-12);
  EXPECT_NEAR(thorvald_base::normalizeAngle(2 * kPi + 0.25), 0.25, 1e-12);
  EXPECT_NEAR(thorvald_base::angleDiff(-3.0, 3.0), 2 * kPi - 6.0, 1e-12);
}
