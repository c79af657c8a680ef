#include <cstdio>
#include <fstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "thorvald_map/map_file.h"
#include "greenhouse_rail_nav/testing/synthetic_greenhouse_map.h"

using namespace greenhouse_rail_nav;

namespace {

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "/greenhouse_rail_nav_" + std::to_string(::getpid()) + "_" + name;
}

// A 3x2 binary PGM: top row 0 (black), 254 (white), 205 (grey); bottom row 254, 100, 0.
void writePgm(const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n3 2\n255\n";
  const unsigned char pixels[6] = {0, 254, 205, 254, 100, 0};
  out.write(reinterpret_cast<const char*>(pixels), 6);
}

void writeYaml(const std::string& path, const std::string& image, int negate, const std::string& extra = "") {
  std::ofstream out(path);
  out << "image: " << image << "\nresolution: 0.05\norigin: [-1.0, 2.0, 0.0]\nnegate: " << negate
      << "\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
      << extra;
}

}  // namespace

TEST(MapFile, ReadsTrinaryMapLikeMapServer) {
  const std::string pgm = tempPath("a.pgm"), yaml = tempPath("a.yaml");
  writePgm(pgm);
  writeYaml(yaml, pgm.substr(pgm.find_last_of('/') + 1), 0);
  thorvald_map::OccupancyGrid map;
  std::string error;
  ASSERT_TRUE(thorvald_map::loadMap(yaml, &map, &error)) << error;
  ASSERT_EQ(map.width, 3);
  ASSERT_EQ(map.height, 2);
  EXPECT_DOUBLE_EQ(map.resolution_m, 0.05);
  EXPECT_DOUBLE_EQ(map.origin.x, -1.0);
  EXPECT_DOUBLE_EQ(map.origin.y, 2.0);
  // Image row 0 is the map's top row (grid row 1). occ = (255 - p) / 255.
  EXPECT_EQ(map.at(0, 1), thorvald_map::kOccupied);  // p 0: occ 1.0
  EXPECT_EQ(map.at(1, 1), thorvald_map::kFree);      // p 254: occ 0.004
  EXPECT_EQ(map.at(2, 1), thorvald_map::kUnknown);   // p 205: occ 0.196, not < free_thresh
  EXPECT_EQ(map.at(0, 0), thorvald_map::kFree);
  EXPECT_EQ(map.at(1, 0), thorvald_map::kUnknown);  // p 100: occ 0.61
  EXPECT_EQ(map.at(2, 0), thorvald_map::kOccupied);
  EXPECT_TRUE(map.cellCentre(0, 0).isApprox(Eigen::Vector2d(-0.975, 2.025)));
  std::remove(pgm.c_str());
  std::remove(yaml.c_str());
}

TEST(MapFile, NegateSwapsFreeAndOccupied) {
  const std::string pgm = tempPath("b.pgm"), yaml = tempPath("b.yaml");
  writePgm(pgm);
  writeYaml(yaml, pgm, 1);  // absolute image path
  thorvald_map::OccupancyGrid map;
  std::string error;
  ASSERT_TRUE(thorvald_map::loadMap(yaml, &map, &error)) << error;
  EXPECT_EQ(map.at(0, 1), thorvald_map::kFree);
  EXPECT_EQ(map.at(1, 1), thorvald_map::kOccupied);
  std::remove(pgm.c_str());
  std::remove(yaml.c_str());
}

TEST(MapFile, ErrorsNameTheProblem) {
  thorvald_map::OccupancyGrid map;
  std::string error;
  EXPECT_FALSE(thorvald_map::loadMap(tempPath("missing.yaml"), &map, &error));
  EXPECT_NE(error.find("missing.yaml"), std::string::npos);

  const std::string yaml = tempPath("c.yaml");
  {
    std::ofstream out(yaml);
    out << "image: x.pgm\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  }
  EXPECT_FALSE(thorvald_map::loadMap(yaml, &map, &error));
  EXPECT_NE(error.find("'resolution'"), std::string::npos) << error;

  writeYaml(yaml, "does_not_exist.pgm", 0);
  EXPECT_FALSE(thorvald_map::loadMap(yaml, &map, &error));
  EXPECT_NE(error.find("cannot read image"), std::string::npos) << error;

  writeYaml(yaml, "x.pgm", 0, "mode: raw\n");
  EXPECT_FALSE(thorvald_map::loadMap(yaml, &map, &error));
  EXPECT_NE(error.find("'mode'"), std::string::npos) << error;
  std::remove(yaml.c_str());
}

TEST(MapFile, SaveThenLoadGivesTheSameCells) {
  GreenhouseLayout layout;
  layout.rail_sets = 4;
  const thorvald_map::OccupancyGrid original = makeGreenhouseMap(layout).map;
  const std::string yaml = tempPath("d.yaml");
  std::string error;
  ASSERT_TRUE(thorvald_map::saveMap(original, yaml, &error)) << error;
  thorvald_map::OccupancyGrid loaded;
  ASSERT_TRUE(thorvald_map::loadMap(yaml, &loaded, &error)) << error;
  ASSERT_EQ(loaded.width, original.width);
  ASSERT_EQ(loaded.height, original.height);
  EXPECT_NEAR(loaded.origin.x, original.origin.x, 1e-6);
  EXPECT_EQ(loaded.data, original.data);
  std::remove(yaml.c_str());
  std::remove((yaml.substr(0, yaml.size() - 5) + ".pgm").c_str());
}

TEST(MapFile, ReadsTheMappersWallSurfaceAndRefusesABrokenOne) {
  const std::string pgm = tempPath("s.pgm"), yaml = tempPath("s.yaml"), surface = tempPath("s.surface");
  writePgm(pgm);
  const std::string image = pgm.substr(pgm.find_last_of('/') + 1);
  const std::string surface_name = surface.substr(surface.find_last_of('/') + 1);
  writeYaml(yaml, image, 0, "wall_surface: " + surface_name + "\n");
  auto write_surface = [&](const std::string& body) {
    std::ofstream out(surface);
    out << "# thorvald_navigation wall surface: cell_x cell_y mean_x mean_y hits\nsize 3 2\n" << body;
  };
  // Cell (2, 0) spans x [-0.90, -0.85], y [2.00, 2.05].
  write_surface("2 0 -0.861 2.013 7\n");
  thorvald_map::OccupancyGrid map;
  std::string error;
  ASSERT_TRUE(thorvald_map::loadMap(yaml, &map, &error)) << error;
  ASSERT_EQ(map.surface.hits.size(), map.data.size());
  EXPECT_FLOAT_EQ(map.surface.hits[2], 7.0f);
  EXPECT_NEAR(map.surface.mean_m[2].x(), -0.861, 1e-6);
  EXPECT_NEAR(map.surface.mean_m[2].y(), 2.013, 1e-6);
  EXPECT_FLOAT_EQ(map.surface.hits[0], 0.0f);

  write_surface("2 0 -0.70 2.013 7\n");  // the mean lies outside its cell
  EXPECT_FALSE(thorvald_map::loadMap(yaml, &map, &error));
  EXPECT_NE(error.find("outside its cell"), std::string::npos) << error;
  {
    std::ofstream out(surface);
    out << "# thorvald_navigation wall surface: cell_x cell_y mean_x mean_y hits\nsize 4 2\n";
  }
  EXPECT_FALSE(thorvald_map::loadMap(yaml, &map, &error));
  EXPECT_NE(error.find("size 3 2"), std::string::npos) << error;
  std::remove(surface.c_str());
  EXPECT_FALSE(thorvald_map::loadMap(yaml, &map, &error));
  EXPECT_NE(error.find("cannot open wall surface"), std::string::npos) << error;
  std::remove(pgm.c_str());
  std::remove(yaml.c_str());
}
