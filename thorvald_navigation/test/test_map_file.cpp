#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "thorvald_navigation/map_file.h"

using thorvald_navigation::Grid2D;

namespace {

std::string tempStem(const std::string& name) { return ::testing::TempDir() + "thorvald_nav_" + name; }

TEST(MapFile, RoundTripKeepsGeometryAndTrinaryValues) {
  Grid2D g(7, 5, 0.05, -1.25, 2.5, thorvald_navigation::kUnknown);
  g.at(0, 0) = 0;
  g.at(6, 4) = 100;
  g.at(3, 2) = 70;  // occupied
  g.at(4, 2) = 10;  // free
  g.at(5, 2) = 50;  // unknown
  const std::string stem = tempStem("roundtrip");
  ASSERT_EQ(saveMap(g, stem), "");
  Grid2D back;
  ASSERT_EQ(loadMap(stem + ".yaml", &back), "");
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_NEAR(back.resolution_m, 0.05, 1e-9);
  EXPECT_NEAR(back.origin_x_m, -1.25, 1e-9);
  EXPECT_NEAR(back.origin_y_m, 2.5, 1e-9);
  EXPECT_EQ(back.at(0, 0), 0);
  EXPECT_EQ(back.at(6, 4), 100);
  EXPECT_EQ(back.at(3, 2), 100);
  EXPECT_EQ(back.at(4, 2), 0);
  EXPECT_EQ(back.at(5, 2), -1);
  EXPECT_EQ(back.at(1, 1), -1);
}

TEST(MapFile, ImageRowsAreFlippedAsMapServerExpects) {
  Grid2D g(2, 2, 0.1, 0.0, 0.0, 0);
  g.at(0, 1) = 100;  // top-left in the image
  const std::string stem = tempStem("flip");
  ASSERT_EQ(saveMap(g, stem), "");
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

TEST(MapFile, BadInputNamesTheProblem) {
  Grid2D g;
  EXPECT_NE(saveMap(g, tempStem("empty")), "");
  Grid2D out;
  EXPECT_NE(loadMap(tempStem("does_not_exist") + ".yaml", &out).find("cannot read"), std::string::npos);
  const std::string yaml = tempStem("rotated") + ".yaml";
  std::ofstream(yaml) << "image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0.3]\n";
  EXPECT_NE(loadMap(yaml, &out).find("rotated"), std::string::npos);
  const std::string missing = tempStem("missing_key") + ".yaml";
  std::ofstream(missing) << "image: x.pgm\norigin: [0, 0, 0]\n";
  EXPECT_NE(loadMap(missing, &out).find("resolution"), std::string::npos);
  const std::string no_image = tempStem("no_image") + ".yaml";
  std::ofstream(no_image) << "image: nothing_here.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  EXPECT_NE(loadMap(no_image, &out).find("cannot open image"), std::string::npos);
  const std::string truncated = tempStem("truncated");
  std::ofstream(truncated + ".pgm", std::ios::binary) << "P5\n4 4\n255\nab";
  std::ofstream(truncated + ".yaml") << "image: "
                                     << "thorvald_nav_truncated.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  EXPECT_NE(loadMap(truncated + ".yaml", &out).find("ends early"), std::string::npos);
}

}  // namespace
