#include <cmath>

#include <gtest/gtest.h>

#include "thorvald_navigation/distance_field.h"

using thorvald_navigation::DistanceField;
using thorvald_navigation::Grid2D;

namespace {

TEST(DistanceField, MatchesBruteForceEuclideanDistance) {
  Grid2D g(40, 30, 0.1, -2.0, 1.0, 0);
  const int walls[][2] = {{3, 4}, {20, 20}, {39, 0}, {10, 29}, {25, 7}};
  for (const auto& w : walls) g.at(w[0], w[1]) = 100;
  const DistanceField f(g, 10.0);
  EXPECT_EQ(f.occupiedCells(), 5);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      double best = 1e9;
      for (const auto& w : walls) best = std::min(best, std::hypot(x - w[0], y - w[1]) * 0.1);
      ASSERT_NEAR(f.cellDistance(x, y), best, 1e-5) << x << "," << y;
    }
}

TEST(DistanceField, ClampsInterpolatesAndPointsAwayFromWalls) {
  Grid2D g(50, 50, 0.05, 0.0, 0.0, 0);
  for (int y = 0; y < 50; ++y) g.at(25, y) = 100;  // a wall along x = 1.275 m
  const DistanceField f(g, 0.5);
  EXPECT_NEAR(f.cellDistance(0, 10), 0.5, 1e-6);
  Eigen::Vector2d grad;
  const double d = f.distance({1.275 + 0.2, 1.0}, &grad);
  EXPECT_NEAR(d, 0.2, 1e-6);
  EXPECT_NEAR(grad.x(), 1.0, 1e-6);
  EXPECT_NEAR(grad.y(), 0.0, 1e-6);
  f.distance({1.275 - 0.2, 1.0}, &grad);
  EXPECT_NEAR(grad.x(), -1.0, 1e-6);
  EXPECT_NEAR(f.distance({-5.0, 1.0}, &grad), 0.5, 1e-12);  // outside: max distance, no gradient
  EXPECT_EQ(grad.norm(), 0.0);
}

TEST(DistanceField, EmptyAndWallFreeGrids) {
  const DistanceField empty(Grid2D(), 1.0);
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.distance({0, 0}), 1.0);
  const DistanceField free_only(Grid2D(10, 10, 0.1, 0, 0, 0), 0.7);
  EXPECT_NEAR(free_only.cellDistance(5, 5), 0.7, 1e-6);
  const DistanceField unknown_only(Grid2D(10, 10, 0.1, 0, 0, -1), 0.7);  // unknown is not a wall
  EXPECT_EQ(unknown_only.occupiedCells(), 0);
}

}  // namespace
