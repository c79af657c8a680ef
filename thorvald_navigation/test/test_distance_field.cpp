#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "thorvald_navigation/distance_field.h"

using thorvald_map::OccupancyGrid;
using thorvald_navigation::DistanceField;

namespace {

TEST(DistanceField, MatchesBruteForceEuclideanDistance) {
  thorvald_map::OccupancyGrid g(40, 30, 0.1, -2.0, 1.0, 0);
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
  thorvald_map::OccupancyGrid g(50, 50, 0.05, 0.0, 0.0, 0);
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
  const DistanceField empty(thorvald_map::OccupancyGrid(), 1.0);
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.distance({0, 0}), 1.0);
  const DistanceField free_only(thorvald_map::OccupancyGrid(10, 10, 0.1, 0, 0, 0), 0.7);
  EXPECT_NEAR(free_only.cellDistance(5, 5), 0.7, 1e-6);
  const DistanceField unknown_only(thorvald_map::OccupancyGrid(10, 10, 0.1, 0, 0, -1), 0.7);  // unknown is not a wall
  EXPECT_EQ(unknown_only.occupiedCells(), 0);
}

}  // namespace

namespace {

// The field updated cell by cell equals the field built anew from the same grid, with and without a wall surface:
// random walls drawn and erased over several rounds.
TEST(DistanceField, UpdateEqualsRebuild) {
  std::mt19937 rng(5);
  thorvald_map::OccupancyGrid g(150, 120, 0.025, -1.0, 2.0, 0);
  thorvald_map::WallSurface s;
  s.hits.assign(g.data.size(), 0.0f);
  s.mean_m.assign(g.data.size(), Eigen::Vector2f::Zero());
  std::uniform_int_distribution<int> ux(0, 149), uy(0, 119), len(3, 40);
  std::uniform_real_distribution<double> sub(0.0, 1.0);
  auto draw = [&](std::vector<int>* changed, std::vector<int>* moved, std::int8_t value) {
    const int x0 = ux(rng), y0 = uy(rng), n = len(rng);
    const bool horizontal = sub(rng) < 0.5;
    for (int k = 0; k < n; ++k) {
      const int x = horizontal ? x0 + k : x0, y = horizontal ? y0 : y0 + k;
      if (!g.inside(x, y)) break;
      const std::size_t i = g.index(x, y);
      if (g.data[i] != value) changed->push_back(static_cast<int>(i));
      g.data[i] = value;
      if (value == 100) {
        const Eigen::Vector2d c = g.cellCentre(x, y);
        s.mean_m[i] = Eigen::Vector2f(static_cast<float>(c.x() + (sub(rng) - 0.5) * 0.025),
                                      static_cast<float>(c.y() + (sub(rng) - 0.5) * 0.025));
        s.hits[i] += 1.0f;
        moved->push_back(static_cast<int>(i));
      }
    }
  };
  std::vector<int> changed, moved;
  for (int k = 0; k < 6; ++k) draw(&changed, &moved, 100);
  for (const bool with_surface : {false, true}) {
    DistanceField f(g, 0.3, 65, true, with_surface ? &s : nullptr);
    for (int round = 0; round < 5; ++round) {
      changed.clear();
      moved.clear();
      for (int k = 0; k < 3; ++k) draw(&changed, &moved, 100);
      draw(&changed, &moved, 0);
      f.update(g, with_surface ? &s : nullptr, changed, moved);
      const DistanceField fresh(g, 0.3, 65, true, with_surface ? &s : nullptr);
      ASSERT_EQ(f.occupiedCells(), fresh.occupiedCells());
      for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x)
          ASSERT_NEAR(f.cellDistance(x, y), fresh.cellDistance(x, y), 1e-6) << x << "," << y << " round " << round;
      for (int k = 0; k < 2000; ++k) {
        const Eigen::Vector2d p(-1.0 + 3.75 * sub(rng), 2.0 + 3.0 * sub(rng));
        ASSERT_NEAR(f.distance(p), fresh.distance(p), 1e-6) << p.transpose() << " round " << round;
      }
    }
  }
}

}  // namespace
