#include <cstdio>
#include <fstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "thorvald_map/map_file.h"

using thorvald_map::loadMap;
using thorvald_map::OccupancyGrid;
using thorvald_map::saveMap;

namespace {

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "/thorvald_map_" + std::to_string(::getpid()) + "_" + name;
}
std::string baseName(const std::string& path) { return path.substr(path.find_last_of('/') + 1); }

constexpr const char* kSurfaceHeader = "# thorvald_navigation wall surface: cell_x cell_y mean_x mean_y hits\n";
constexpr const char* kThresholds = "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";

// A 3x2 map as both earlier writers wrote it: headland_mapper's (a comment in the PGM header, a wall surface) and the
// map analyzer's (OpenCV's PGM header, no comment, no surface). Top row 0, 254, 205; bottom row 254, 100, 0.
void writeOldMap(const std::string& stem, bool mapper_style) {
  std::ofstream pgm(stem + ".pgm", std::ios::binary);
  pgm << (mapper_style ? "P5\n# thorvald_navigation map\n3 2\n255\n" : "P5\n3 2\n255\n");
  const unsigned char pixels[6] = {0, 254, 205, 254, 100, 0};
  pgm.write(reinterpret_cast<const char*>(pixels), 6);
  std::ofstream yaml(stem + ".yaml");
  yaml.precision(9);
  yaml << "image: " << baseName(stem) << ".pgm\nresolution: 0.05\norigin: [-1, 2, " << (mapper_style ? "0.0" : "0")
       << "]\n"
       << kThresholds;
  if (mapper_style) {
    yaml << "wall_surface: " << baseName(stem) << ".surface\n";
    std::ofstream(stem + ".surface") << kSurfaceHeader << "size 3 2\n2 0 -0.861 2.013 7\n";
  }
}

TEST(MapFile, RoundTripKeepsGeometryValuesAndSurface) {
  OccupancyGrid g(7, 5, 0.05, -1.25, 2.5);
  g.at(0, 0) = 0;
  g.at(6, 4) = 100;
  g.at(3, 2) = 70;  // written occupied
  g.at(4, 2) = 10;  // written free
  g.at(5, 2) = 50;  // written unknown
  g.surface.hits.assign(g.data.size(), 0.0f);
  g.surface.mean_m.assign(g.data.size(), Eigen::Vector2f::Zero());
  g.surface.hits[g.index(6, 4)] = 7.0f;
  g.surface.mean_m[g.index(6, 4)] = Eigen::Vector2f(-0.9387f, 2.7112f);  // cell (6, 4): x -0.95..-0.9, y 2.7..2.75
  const std::string stem = tempPath("roundtrip");
  std::string error;
  ASSERT_TRUE(saveMap(g, stem + ".yaml", &error)) << error;
  OccupancyGrid back;
  ASSERT_TRUE(loadMap(stem + ".yaml", &back, &error)) << error;
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_NEAR(back.resolution_m, 0.05, 1e-12);
  EXPECT_NEAR(back.origin.x, -1.25, 1e-12);
  EXPECT_NEAR(back.origin.y, 2.5, 1e-12);
  EXPECT_EQ(back.origin.yaw, 0.0);
  EXPECT_EQ(back.at(0, 0), 0);
  EXPECT_EQ(back.at(6, 4), 100);
  EXPECT_EQ(back.at(3, 2), 100);
  EXPECT_EQ(back.at(4, 2), 0);
  EXPECT_EQ(back.at(5, 2), -1);
  EXPECT_EQ(back.at(1, 1), -1);
  ASSERT_EQ(back.surface.size(), g.data.size());
  EXPECT_EQ(back.surface.hits[g.index(6, 4)], 7.0f);
  EXPECT_EQ(back.surface.mean_m[g.index(6, 4)], g.surface.mean_m[g.index(6, 4)]);  // written with float precision
  EXPECT_EQ(back.surface.hits[g.index(0, 0)], 0.0f);
  // A grid without a surface is written without one and read back without one; a stem works as the path too.
  g.surface = thorvald_map::WallSurface();
  ASSERT_TRUE(saveMap(g, stem, &error)) << error;
  ASSERT_TRUE(loadMap(stem + ".yaml", &back, &error)) << error;
  EXPECT_TRUE(back.surface.empty());
}

TEST(MapFile, RotatedOriginRoundTripsAndCanBeRefused) {
  OccupancyGrid g(3, 2, 0.1, thorvald_base::Pose2D(1.0, -2.0, 0.3), thorvald_map::kFree);
  g.at(1, 1) = thorvald_map::kOccupied;
  const std::string stem = tempPath("rotated");
  std::string error;
  ASSERT_TRUE(saveMap(g, stem, &error)) << error;
  OccupancyGrid back;
  ASSERT_TRUE(loadMap(stem + ".yaml", &back, &error)) << error;
  EXPECT_NEAR(back.origin.yaw, 0.3, 1e-9);
  EXPECT_EQ(back.data, g.data);
  thorvald_map::MapLoadOptions unrotated;
  unrotated.allow_rotated_origin = false;
  EXPECT_FALSE(loadMap(stem + ".yaml", &back, &error, unrotated));
  EXPECT_NE(error.find("rotated"), std::string::npos) << error;
  EXPECT_NE(error.find("'origin'"), std::string::npos) << error;
  // A wall surface needs an unrotated origin, both ways.
  g.surface.hits.assign(g.data.size(), 0.0f);
  g.surface.mean_m.assign(g.data.size(), Eigen::Vector2f::Zero());
  EXPECT_FALSE(saveMap(g, stem, &error));
  EXPECT_NE(error.find("unrotated"), std::string::npos) << error;
  std::ofstream(stem + ".yaml", std::ios::app) << "wall_surface: x.surface\n";
  EXPECT_FALSE(loadMap(stem + ".yaml", &back, &error));
  EXPECT_NE(error.find("'wall_surface' needs an unrotated origin"), std::string::npos) << error;
}

TEST(MapFile, FilesOfBothEarlierWritersLoad) {
  for (const bool mapper_style : {true, false}) {
    const std::string stem = tempPath(mapper_style ? "old_mapper" : "old_analyzer");
    writeOldMap(stem, mapper_style);
    OccupancyGrid map;
    std::string error;
    ASSERT_TRUE(loadMap(stem + ".yaml", &map, &error)) << error;
    ASSERT_EQ(map.width, 3);
    ASSERT_EQ(map.height, 2);
    // Image row 0 is the map's top row (grid row 1); occupancy = (255 - pixel) / 255.
    EXPECT_EQ(map.at(0, 1), thorvald_map::kOccupied);  // 0: 1.0
    EXPECT_EQ(map.at(1, 1), thorvald_map::kFree);      // 254: 0.004
    EXPECT_EQ(map.at(2, 1), thorvald_map::kUnknown);   // 205: 0.196, not < free_thresh
    EXPECT_EQ(map.at(0, 0), thorvald_map::kFree);
    EXPECT_EQ(map.at(1, 0), thorvald_map::kUnknown);  // 100: 0.61
    EXPECT_EQ(map.at(2, 0), thorvald_map::kOccupied);
    EXPECT_TRUE(map.cellCentre(0, 0).isApprox(Eigen::Vector2d(-0.975, 2.025)));
    EXPECT_EQ(map.surface.empty(), !mapper_style);
    if (mapper_style) {
      EXPECT_FLOAT_EQ(map.surface.hits[2], 7.0f);
      EXPECT_NEAR(map.surface.mean_m[2].x(), -0.861, 1e-6);
      EXPECT_NEAR(map.surface.mean_m[2].y(), 2.013, 1e-6);
    }
  }
}

TEST(MapFile, NegateScaleAndAsciiPgm) {
  const std::string stem = tempPath("ascii");
  std::ofstream(stem + ".pgm") << "P2\n# comment\n3 1\n100\n0 100 50\n";
  std::ofstream(stem + ".yaml") << "image: " << stem << ".pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 1\n"
                                << "occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: scale\n";
  OccupancyGrid map;
  std::string error;
  ASSERT_TRUE(loadMap(stem + ".yaml", &map, &error)) << error;  // absolute image path
  EXPECT_EQ(map.at(0, 0), thorvald_map::kFree);                 // negated: white is occupied
  EXPECT_EQ(map.at(1, 0), thorvald_map::kOccupied);
  EXPECT_EQ(map.at(2, 0), 66);  // scale: 99 (0.5 - 0.196) / (0.65 - 0.196)
}

std::string loadError(const std::string& yaml_path, std::uint64_t max_cells = 200000000) {
  OccupancyGrid map;
  std::string error;
  thorvald_map::MapLoadOptions options;
  options.max_cells = max_cells;
  EXPECT_FALSE(loadMap(yaml_path, &map, &error, options)) << yaml_path;
  return error;
}

TEST(MapFile, MalformedMapsAreRefusedNamingFileAndKey) {
  const std::string yaml = tempPath("bad.yaml");
  EXPECT_NE(loadError(tempPath("missing.yaml")).find("missing.yaml"), std::string::npos);
  std::ofstream(yaml) << "image: x.pgm\norigin: [0, 0, 0]\n" << kThresholds;
  EXPECT_NE(loadError(yaml).find(yaml + ": missing key 'resolution'"), std::string::npos) << loadError(yaml);
  std::ofstream(yaml) << "image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n";
  EXPECT_NE(loadError(yaml).find("'occupied_thresh'"), std::string::npos) << loadError(yaml);
  std::ofstream(yaml) << "image: x.pgm\nresolution: fine\norigin: [0, 0, 0]\n" << kThresholds;
  EXPECT_NE(loadError(yaml).find("key 'resolution' is not"), std::string::npos) << loadError(yaml);
  std::ofstream(yaml) << "image: x.pgm\nresolution: 0.05\norigin: [0, 0]\n" << kThresholds;
  EXPECT_NE(loadError(yaml).find("'origin' must be [x, y, yaw]"), std::string::npos) << loadError(yaml);
  std::ofstream(yaml) << "image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n" << kThresholds << "mode: raw\n";
  EXPECT_NE(loadError(yaml).find("'mode'"), std::string::npos) << loadError(yaml);
  std::ofstream(yaml) << "image: nothing_here.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n" << kThresholds;
  EXPECT_NE(loadError(yaml).find("cannot read image"), std::string::npos) << loadError(yaml);
  EXPECT_NE(loadError(yaml).find("nothing_here.pgm"), std::string::npos);

  const std::string stem = tempPath("truncated");
  std::ofstream(stem + ".pgm", std::ios::binary) << "P5\n4 4\n255\nab";
  std::ofstream(stem + ".yaml") << "image: " << baseName(stem) << ".pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
                                << kThresholds;
  EXPECT_NE(loadError(stem + ".yaml").find("ends early"), std::string::npos) << loadError(stem + ".yaml");
  std::ofstream(stem + ".pgm", std::ios::binary) << "P5\n# comment\n100000 50000\n255\n";
  EXPECT_NE(loadError(stem + ".yaml").find("100000 x 50000"), std::string::npos) << loadError(stem + ".yaml");
  std::ofstream(stem + ".pgm", std::ios::binary) << "P5\n30 20\n255\n" << std::string(600, '\xfe');
  EXPECT_NE(loadError(stem + ".yaml", 500).find("30 x 20"), std::string::npos) << loadError(stem + ".yaml", 500);
}

TEST(MapFile, BrokenWallSurfaceIsRefusedNamingFileAndLine) {
  const std::string stem = tempPath("surface");
  writeOldMap(stem, true);
  const std::string surface = stem + ".surface";
  auto error_with = [&](const std::string& body) {
    std::ofstream(surface) << body;
    return loadError(stem + ".yaml");
  };
  std::string e = error_with(std::string(kSurfaceHeader) + "size 3 2\n2 0 -0.70 2.013 7\n");  // mean outside
  EXPECT_NE(e.find(surface + ":3: mean end point outside its cell"), std::string::npos) << e;
  e = error_with(std::string(kSurfaceHeader) + "size 3 2\n\n9 0 -0.861 2.013 7\n");  // cell outside the map
  EXPECT_NE(e.find(surface + ":4: expected 'cell_x cell_y mean_x mean_y hits'"), std::string::npos) << e;
  e = error_with(std::string(kSurfaceHeader) + "size 3 2\n2 0 -0.861 2.013 0\n");  // no hits
  EXPECT_NE(e.find(":3:"), std::string::npos) << e;
  e = error_with(std::string(kSurfaceHeader) + "size 4 2\n");
  EXPECT_NE(e.find(surface + ":2: must be 'size 3 2'"), std::string::npos) << e;
  e = error_with("# some other wall surface\nsize 3 2\n");  // only the mapper's header is a wall surface file
  EXPECT_NE(e.find(surface + ":1: not a wall surface file"), std::string::npos) << e;
  std::remove(surface.c_str());
  EXPECT_NE(loadError(stem + ".yaml").find("cannot open wall surface"), std::string::npos);
}

TEST(MapFile, SaveRefusesAnUnusableGrid) {
  OccupancyGrid g;
  std::string error;
  EXPECT_FALSE(saveMap(g, tempPath("empty"), &error));
  EXPECT_NE(error.find("width and height"), std::string::npos) << error;
  g = OccupancyGrid(2, 2, 0.1, 0.0, 0.0);
  EXPECT_FALSE(saveMap(g, "/nonexistent_dir/map.yaml", &error));
  EXPECT_NE(error.find("/nonexistent_dir/map.pgm"), std::string::npos) << error;
}

}  // namespace
