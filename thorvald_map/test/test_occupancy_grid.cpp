#include <cmath>

#include <gtest/gtest.h>

#include "thorvald_map/occupancy_grid.h"

using thorvald_map::OccupancyGrid;

namespace {

TEST(OccupancyGrid, CellsOfAnUnrotatedGrid) {
  OccupancyGrid g(4, 3, 0.5, -1.0, 2.0, thorvald_map::kFree);
  EXPECT_EQ(g.data.size(), 12u);
  g.at(3, 2) = thorvald_map::kOccupied;
  EXPECT_EQ(g.data[g.index(3, 2)], thorvald_map::kOccupied);
  EXPECT_TRUE(g.cellCentre(0, 0).isApprox(Eigen::Vector2d(-0.75, 2.25)));
  EXPECT_EQ(g.cellOf({0.9, 3.4}), Eigen::Vector2i(3, 2));
  EXPECT_EQ(g.cellOf({-1.1, 1.9}), Eigen::Vector2i(-1, -1));  // outside, still the cell it would be
  int cx = -7, cy = -7;
  EXPECT_FALSE(g.worldToCell({-1.1, 1.9}, &cx, &cy));
  EXPECT_EQ(cx, -7);
  ASSERT_TRUE(g.worldToCell({0.9, 3.4}, &cx, &cy));
  EXPECT_EQ(cx, 3);
  EXPECT_EQ(cy, 2);
  EXPECT_EQ(g.valueAt({0.9, 3.4}), thorvald_map::kOccupied);
  EXPECT_EQ(g.valueAt({5.0, 5.0}), thorvald_map::kUnknown);
  EXPECT_DOUBLE_EQ(g.widthMeters(), 2.0);
  EXPECT_DOUBLE_EQ(g.heightMeters(), 1.5);
  EXPECT_EQ(g.check(), "");
}

TEST(OccupancyGrid, ARotatedGridTurnsItsCells) {
  // Origin at (1, 1), turned a quarter: columns go along +y, rows along -x.
  const OccupancyGrid g(2, 2, 1.0, thorvald_base::Pose2D(1.0, 1.0, M_PI / 2));
  EXPECT_TRUE(g.cellCentre(0, 0).isApprox(Eigen::Vector2d(0.5, 1.5)));
  EXPECT_TRUE(g.cellCentre(1, 0).isApprox(Eigen::Vector2d(0.5, 2.5)));
  EXPECT_TRUE(g.cellCentre(0, 1).isApprox(Eigen::Vector2d(-0.5, 1.5)));
  EXPECT_EQ(g.cellOf({-0.5, 2.5}), Eigen::Vector2i(1, 1));
  for (int cy = 0; cy < 2; ++cy)
    for (int cx = 0; cx < 2; ++cx) EXPECT_EQ(g.cellOf(g.cellCentre(cx, cy)), Eigen::Vector2i(cx, cy));
}

TEST(OccupancyGrid, CheckNamesWhatIsWrong) {
  OccupancyGrid g(2, 2, 0.1, 0.0, 0.0);
  g.data.pop_back();
  EXPECT_NE(g.check().find("data size 3"), std::string::npos) << g.check();
  g = OccupancyGrid(2, 2, 0.0, 0.0, 0.0);
  EXPECT_NE(g.check().find("resolution"), std::string::npos);
  g = OccupancyGrid(2, 2, 0.1, NAN, 0.0);
  EXPECT_NE(g.check().find("origin"), std::string::npos);
  g = OccupancyGrid(2, 2, 0.1, 0.0, 0.0);
  g.surface.hits.assign(3, 0.0f);
  g.surface.mean_m.assign(3, Eigen::Vector2f::Zero());
  EXPECT_NE(g.check().find("wall surface has 3 cells"), std::string::npos) << g.check();
  EXPECT_NE(OccupancyGrid().check(), "");
}

}  // namespace
