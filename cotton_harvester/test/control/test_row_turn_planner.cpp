// The headland turn from one row's end into the next: its shape, the room it needs, and how it enters the row.
#include <gtest/gtest.h>

#include <cmath>

#include "cotton_harvester/control/pure_pursuit.h"
#include "cotton_harvester/control/row_turn_planner.h"

namespace cc = cotton_harvester::control;

namespace {

constexpr double kRowSpacing = 0.9144;

/// Radius of the circle through three points (infinity when they are in line).
double circleRadius(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const double cross = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  if (std::abs(cross) < 1e-12) return std::numeric_limits<double>::infinity();
  return (b - a).norm() * (c - b).norm() * (c - a).norm() / (2.0 * std::abs(cross));
}

double minRadius(const std::vector<Eigen::Vector2d>& pts) {
  double r = std::numeric_limits<double>::infinity();
  for (size_t i = 2; i < pts.size(); ++i) r = std::min(r, circleRadius(pts[i - 2], pts[i - 1], pts[i]));
  return r;
}

}  // namespace

TEST(RowTurnPlanner, RowsOverForAUTurn) {
  // The rover's full articulation gives R = 2.197 m: 2 R = 4.39 m is 4.8 rows, so the fifth row over.
  EXPECT_EQ(cc::rowsOverForUTurn(kRowSpacing, cc::minTurnRadius(45.0, 0.91)), 5);
  EXPECT_EQ(cc::rowsOverForUTurn(kRowSpacing, 2.5), 6);
  EXPECT_EQ(cc::rowsOverForUTurn(1.0, 0.5), 1);
  EXPECT_THROW(cc::rowsOverForUTurn(0.0, 1.0), std::invalid_argument);
}

TEST(RowTurnPlanner, NextRowIsAnOmegaInsideTheHeadland) {
  cc::RowTurnParams p;
  p.turn_radius_m = 2.5;
  p.straight_m = 0.5;
  const cc::RowTurn turn = cc::planRowTurn({20.0, 0.0}, 0.0, kRowSpacing, p);
  EXPECT_EQ(turn.shape, cc::TurnShape::kOmega);
  // Independently: the middle circle's centre is sqrt((2R)^2 - ((d + 2R) / 2)^2) past the straight.
  const double r = 2.5, half = 0.5 * (kRowSpacing + 2 * r);
  const double depth = 0.5 + std::sqrt(4 * r * r - half * half) + r;
  EXPECT_NEAR(turn.depth_m, depth, 0.01);
  EXPECT_NEAR(turn.min_lateral_m, 0.5 * kRowSpacing - r, 0.01);
  EXPECT_NEAR(turn.max_lateral_m, 0.5 * kRowSpacing + r, 0.01);
  for (const Eigen::Vector2d& q : turn.waypoints) {
    EXPECT_GE(q.x(), 20.0 - 1e-9);  // never back into the rows' block
    EXPECT_LE(q.x(), 20.0 + depth + 1e-6);
  }
  // Starts at the row's end, ends at the next row's end heading back along it.
  EXPECT_NEAR((turn.waypoints.front() - Eigen::Vector2d(20.0, 0.0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((turn.waypoints.back() - Eigen::Vector2d(20.0, kRowSpacing)).norm(), 0.0, 1e-9);
  const Eigen::Vector2d last = turn.waypoints.back() - turn.waypoints[turn.waypoints.size() - 2];
  EXPECT_NEAR(std::atan2(last.y(), last.x()), M_PI, 1e-6);
  // No tighter than the planned radius (the waypoints' chords lose a little).
  EXPECT_GT(minRadius(turn.waypoints), 0.99 * r);
}

TEST(RowTurnPlanner, FarRowIsAUTurnOneRadiusDeep) {
  cc::RowTurnParams p;
  p.turn_radius_m = 2.0;
  const double lateral = 5 * kRowSpacing;                                     // 4.57 m >= 2 R
  const cc::RowTurn turn = cc::planRowTurn({0.0, 0.0}, M_PI_2, -lateral, p);  // heading +y, row to the right
  EXPECT_EQ(turn.shape, cc::TurnShape::kU);
  EXPECT_NEAR(turn.depth_m, p.straight_m + 2.0, 1e-6);
  EXPECT_NEAR(turn.min_lateral_m, -lateral, 1e-9);
  EXPECT_NEAR(turn.max_lateral_m, 0.0, 1e-9);
  // Heading +y, the right is +x.
  EXPECT_NEAR((turn.waypoints.back() - Eigen::Vector2d(lateral, 0.0)).norm(), 0.0, 1e-9);
  EXPECT_GT(minRadius(turn.waypoints), 0.99 * 2.0);
}

TEST(RowTurnPlanner, RightTurnMirrorsTheLeftOne) {
  cc::RowTurnParams p;
  const cc::RowTurn left = cc::planRowTurn({0.0, 0.0}, 0.0, kRowSpacing, p);
  const cc::RowTurn right = cc::planRowTurn({0.0, 0.0}, 0.0, -kRowSpacing, p);
  ASSERT_EQ(left.waypoints.size(), right.waypoints.size());
  for (size_t i = 0; i < left.waypoints.size(); ++i) {
    EXPECT_NEAR(left.waypoints[i].x(), right.waypoints[i].x(), 1e-12);
    EXPECT_NEAR(left.waypoints[i].y(), -right.waypoints[i].y(), 1e-12);
  }
}

TEST(RowTurnPlanner, BadInputIsRefused) {
  cc::RowTurnParams p;
  EXPECT_THROW(cc::planRowTurn({0, 0}, 0.0, 0.0, p), std::invalid_argument);
  EXPECT_THROW(cc::planRowTurn({0, 0}, NAN, 1.0, p), std::invalid_argument);
  p.turn_radius_m = 0.0;
  EXPECT_EQ(p.check(), "turn_radius_m: expected > 0");
  EXPECT_THROW(cc::planRowTurn({0, 0}, 0.0, 1.0, p), std::invalid_argument);
}
