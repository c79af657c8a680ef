// The map files headland_mapper writes and map_localizer reads (thorvald_map's reader and writer), as this package
// uses them: maps saved by stem, unrotated origins only, the wall surface beside the map.
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "thorvald_map/map_file.h"

using thorvald_map::OccupancyGrid;

namespace {

std::string tempStem(const std::string& name) { return ::testing::TempDir() + "thorvald_nav_" + name; }

std::string saveError(const OccupancyGrid& g, const std::string& stem) {
  std::string error;
  return thorvald_map::saveMap(g, stem, &error) ? std::string() : error;
}

/// As map_localizer loads: unrotated origins only.
std::string loadError(const std::string& yaml, OccupancyGrid* grid) {
  thorvald_map::MapLoadOptions unrotated;
  unrotated.allow_rotated_origin = false;
  std::string error;
  return thorvald_map::loadMap(yaml, grid, &error, unrotated) ? std::string() : error;
}

constexpr const char* kKeys = "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";

TEST(MapFile, RoundTripKeepsGeometryAndTrinaryValues) {
  OccupancyGrid g(7, 5, 0.05, -1.25, 2.5, thorvald_map::kUnknown);
  g.at(0, 0) = 0;
  g.at(6, 4) = 100;
  g.at(3, 2) = 70;  // occupied
  g.at(4, 2) = 10;  // free
  g.at(5, 2) = 50;  // unknown
  const std::string stem = tempStem("roundtrip");
  ASSERT_EQ(saveError(g, stem), "");
  OccupancyGrid back;
  ASSERT_EQ(loadError(stem + ".yaml", &back), "");
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_NEAR(back.resolution_m, 0.05, 1e-9);
  EXPECT_NEAR(back.origin.x, -1.25, 1e-9);
  EXPECT_NEAR(back.origin.y, 2.5, 1e-9);
  EXPECT_EQ(back.at(0, 0), 0);
  EXPECT_EQ(back.at(6, 4), 100);
  EXPECT_EQ(back.at(3, 2), 100);
  EXPECT_EQ(back.at(4, 2), 0);
  EXPECT_EQ(back.at(5, 2), -1);
  EXPECT_EQ(back.at(1, 1), -1);
}

TEST(MapFile, ImageRowsAreFlippedAsMapServerExpects) {
  OccupancyGrid g(2, 2, 0.1, 0.0, 0.0, 0);
  g.at(0, 1) = 100;  // top-left in the image
  const std::string stem = tempStem("flip");
  ASSERT_EQ(saveError(g, stem), "");
  std::ifstream in(stem + ".pgm", std::ios::binary);
  std::string magic, comment;
  int w, h, maxval;
  in >> magic;
  in.get();
  std::getline(in, comment);
  in >> w >> h >> maxval;
  in.get();
  const int first_pixel = in.get();
  EXPECT_EQ(magic, "P5");
  EXPECT_EQ(first_pixel, 0);  // black = occupied
}

TEST(MapFile, WallSurfaceRoundTripAndBadSurfaceFile) {
  OccupancyGrid g(4, 3, 0.05, -1.0, 2.0, 0);
  g.at(2, 1) = 100;
  g.surface.hits.assign(12, 0.0f);
  g.surface.mean_m.assign(12, Eigen::Vector2f::Zero());
  g.surface.hits[g.index(2, 1)] = 7.0f;
  g.surface.mean_m[g.index(2, 1)] =
      Eigen::Vector2f(-0.8887f, 2.0612f);  // inside cell (2, 1): x -0.9..-0.85, y 2.05..2.1
  const std::string stem = tempStem("surface");
  ASSERT_EQ(saveError(g, stem), "");
  OccupancyGrid back;
  ASSERT_EQ(loadError(stem + ".yaml", &back), "");
  const thorvald_map::WallSurface& sb = back.surface;
  ASSERT_EQ(sb.size(), 12u);
  EXPECT_EQ(sb.hits[g.index(2, 1)], 7.0f);
  EXPECT_NEAR(sb.mean_m[g.index(2, 1)].x(), -0.8887, 1e-6);
  EXPECT_NEAR(sb.mean_m[g.index(2, 1)].y(), 2.0612, 1e-6);
  EXPECT_EQ(sb.hits[g.index(0, 0)], 0.0f);
  // A map without a surface file leaves the surface empty.
  g.surface = thorvald_map::WallSurface();
  ASSERT_EQ(saveError(g, tempStem("no_surface")), "");
  ASSERT_EQ(loadError(tempStem("no_surface") + ".yaml", &back), "");
  EXPECT_TRUE(back.surface.empty());
  // A mean outside its cell, or a cell outside the map, is refused with the line.
  std::ofstream(stem + ".surface") << "# thorvald_navigation wall surface: cell_x cell_y mean_x mean_y hits\n"
                                   << "size 4 3\n2 1 -0.5 2.06 3\n";
  EXPECT_NE(loadError(stem + ".yaml", &back).find("outside its cell"), std::string::npos);
  std::ofstream(stem + ".surface") << "# thorvald_navigation wall surface: cell_x cell_y mean_x mean_y hits\n"
                                   << "size 4 3\n9 1 -0.5 2.06 3\n";
  EXPECT_NE(loadError(stem + ".yaml", &back).find(":3:"), std::string::npos);
  std::ofstream(stem + ".surface") << "something else\n";
  EXPECT_NE(loadError(stem + ".yaml", &back).find("header"), std::string::npos);
}

TEST(MapFile, BadInputNamesTheProblem) {
  OccupancyGrid g;
  EXPECT_NE(saveError(g, tempStem("empty")), "");
  OccupancyGrid out;
  EXPECT_NE(loadError(tempStem("does_not_exist") + ".yaml", &out).find("cannot read"), std::string::npos);
  const std::string yaml = tempStem("rotated") + ".yaml";
  std::ofstream(yaml) << "image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0.3]\n" << kKeys;
  EXPECT_NE(loadError(yaml, &out).find("rotated"), std::string::npos);
  const std::string missing = tempStem("missing_key") + ".yaml";
  std::ofstream(missing) << "image: x.pgm\norigin: [0, 0, 0]\n" << kKeys;
  EXPECT_NE(loadError(missing, &out).find("resolution"), std::string::npos);
  const std::string no_image = tempStem("no_image") + ".yaml";
  std::ofstream(no_image) << "image: nothing_here.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n" << kKeys;
  EXPECT_NE(loadError(no_image, &out).find("cannot read image"), std::string::npos);
  const std::string truncated = tempStem("truncated");
  std::ofstream(truncated + ".pgm", std::ios::binary) << "P5\n4 4\n255\nab";
  std::ofstream(truncated + ".yaml") << "image: "
                                     << "thorvald_nav_truncated.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
                                     << kKeys;
  EXPECT_NE(loadError(truncated + ".yaml", &out).find("ends early"), std::string::npos);
}

}  // namespace
