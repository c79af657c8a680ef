#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "greenhouse_rail_nav/headland_scan.h"
#include "greenhouse_rail_nav/map_denoise.h"

using namespace greenhouse_rail_nav;

namespace {

// A headland 2 m deep whose right side wall has its face at x = face_x, drawn as a mapper draws it from noisy beam
// ends: every cell an end falls in is occupied, the floor before it free, the wall's inside unknown; the surface
// keeps each cell's mean end point.
thorvald_map::OccupancyGrid noisyWallMap(double face_x, double range_sigma_m, unsigned seed) {
  const double res = 0.025;
  thorvald_map::OccupancyGrid map(200, 80, res, thorvald_base::Pose2D(0.0, 0.0, 0.0), thorvald_map::kUnknown);
  map.surface.hits.assign(map.data.size(), 0.0f);
  map.surface.mean_m.assign(map.data.size(), Eigen::Vector2f::Zero());
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, range_sigma_m);
  for (int r = 0; r < map.height; ++r) {
    const double y = (r + 0.5) * res;
    int first = map.width;
    for (int k = 0; k < 30; ++k) {
      const Eigen::Vector2d end(face_x + noise(rng), y + (k % 5 - 2) * 0.004);
      int c = 0, cr = 0;
      if (!map.worldToCell(end, &c, &cr)) continue;
      const std::size_t i = static_cast<std::size_t>(cr) * map.width + c;
      const float h = ++map.surface.hits[i];
      map.surface.mean_m[i] += (end.cast<float>() - map.surface.mean_m[i]) / h;
      map.at(c, cr) = thorvald_map::kOccupied;
      if (cr == r) first = std::min(first, c);
    }
    for (int c = 0; c < first; ++c) map.at(c, r) = thorvald_map::kFree;
  }
  return map;
}

}  // namespace

TEST(SideWallScan, TheWallSurfaceGivesTheFaceInsideItsCells) {
  HeadlandFrame frame;  // u along x, v along y: the rear wall at y = 0
  for (const double cell_fraction : {0.1, 0.5, 0.9}) {
    const double face = 3.0 + cell_fraction * 0.025;
    thorvald_map::OccupancyGrid map = noisyWallMap(face, 0.008, 7);
    const SideScan with_surface = scanToSideWall(map, frame, 1.0, 1.9, +1.0, 0.5, 5.0);
    ASSERT_TRUE(with_surface.wall_found) << cell_fraction;
    EXPECT_NEAR(with_surface.wall_u, face, 0.003) << "face at " << cell_fraction << " of its cell";
    map.surface = thorvald_map::WallSurface{};
    const SideScan cells_only = scanToSideWall(map, frame, 1.0, 1.9, +1.0, 0.5, 5.0);
    ASSERT_TRUE(cells_only.wall_found);
    // Without the surface the face is the first occupied cell's near face: in front of the true one.
    EXPECT_LT(cells_only.wall_u, face - 0.0015) << cell_fraction;
  }
}

TEST(SideWallScan, TheLeftWallToo) {
  // The same wall seen from its right: mirror the scene by scanning towards -u in a frame whose u points to -x.
  HeadlandFrame frame;
  frame.u = -Eigen::Vector2d::UnitX();
  frame.v = Eigen::Vector2d::UnitY();
  const double face = 3.0 + 0.3 * 0.025;
  const thorvald_map::OccupancyGrid map = noisyWallMap(face, 0.008, 11);
  // u = -x: the start at x = 1 is u = -1, the wall (face at x = face) at u = -face, scanning towards -u is +x.
  const SideScan scan = scanToSideWall(map, frame, -1.0, 1.9, -1.0, 0.5, 5.0);
  ASSERT_TRUE(scan.wall_found);
  EXPECT_NEAR(scan.wall_u, -face, 0.003);
}

TEST(MapDenoise, ADottedFaceIsOneGroupAndIsolatedReturnsAreSpeckle) {
  // A row's face seen at a grazing angle: single cells and pairs 2-5 cells apart over 3 m; isolated returns
  // 0.5 m away from anything.
  thorvald_map::OccupancyGrid map(200, 60, 0.025, thorvald_base::Pose2D(0.0, 0.0, 0.0), thorvald_map::kFree);
  int dotted = 0;
  for (int c = 10, k = 0; c < 130; c += 2 + k % 4, ++k) {
    map.at(c, 20) = thorvald_map::kOccupied;
    ++dotted;
    if (k % 3 == 0) {
      map.at(c + 1, 20) = thorvald_map::kOccupied;
      ++dotted;
    }
  }
  const int noise[][2] = {{40, 45}, {80, 50}, {160, 10}, {161, 10}, {180, 40}};
  for (const auto& n : noise) map.at(n[0], n[1]) = thorvald_map::kOccupied;
  thorvald_map::OccupancyGrid eight = map;
  // 8-connected, every dot is a group of one or two cells: the face is removed with the noise.
  EXPECT_EQ(removeSpeckle(&eight, 0.012), static_cast<std::size_t>(dotted + 5));
  // Linked within 0.15 m the face is one group of dotted cells (> 0.012 m2 = 20 cells) and stays.
  ASSERT_GT(dotted, 20);
  EXPECT_EQ(removeSpeckle(&map, 0.012, 0.15), 5u);
  for (const auto& n : noise) EXPECT_EQ(map.at(n[0], n[1]), thorvald_map::kFree);
  EXPECT_EQ(map.at(10, 20), thorvald_map::kOccupied);
}
