#include <cstdio>
#include <fstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "greenhouse_rail_nav/rail_set_file.h"

using namespace greenhouse_rail_nav;

TEST(RailSetFile, RoundTrip) {
  RailSetFile file;
  file.frame_id = "map";
  file.edge_start = {1.0, 2.0};
  file.edge_end = {11.0, 2.5};
  file.into_rows = {0.0, 1.0};
  for (int i = 0; i < 3; ++i) {
    RailSetEstimate set;
    set.index = i;
    set.rail_frame = thorvald_base::Pose2D(1.5 + i * 1.6, 2.1, 1.57);
    set.target_pose = thorvald_base::Pose2D(1.5 + i * 1.6, 1.3, 1.57);
    set.good = i != 1;
    if (!set.good) set.reason = "no left side wall found";
    file.rail_sets.push_back(set);
  }
  const std::string path = ::testing::TempDir() + "/rail_sets_" + std::to_string(::getpid()) + ".yaml";
  std::string error;
  ASSERT_TRUE(saveRailSetFile(file, path, &error)) << error;
  RailSetFile loaded;
  ASSERT_TRUE(loadRailSetFile(path, &loaded, &error)) << error;
  EXPECT_EQ(loaded.frame_id, "map");
  ASSERT_EQ(loaded.rail_sets.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(loaded.rail_sets[i].index, i);
    EXPECT_NEAR(loaded.rail_sets[i].rail_frame.x, file.rail_sets[i].rail_frame.x, 1e-5);
    EXPECT_NEAR(loaded.rail_sets[i].target_pose.y, file.rail_sets[i].target_pose.y, 1e-5);
    EXPECT_NEAR(loaded.rail_sets[i].target_pose.yaw, 1.57, 1e-5);
  }
  EXPECT_NEAR(loaded.edge_end.y(), 2.5, 1e-6);
  EXPECT_TRUE(loaded.rail_sets[0].good);
  EXPECT_FALSE(loaded.rail_sets[1].good);
  EXPECT_EQ(loaded.rail_sets[1].reason, "no left side wall found");
  std::remove(path.c_str());
}

TEST(RailSetFile, MalformedEntryIsNamed) {
  const std::string path = ::testing::TempDir() + "/rail_sets_bad_" + std::to_string(::getpid()) + ".yaml";
  {
    std::ofstream out(path);
    out << "frame_id: map\nheadland_edge: {start: [0, 0], end: [5, 0], into_rows: [0, 1]}\n"
        << "rail_sets:\n  - {index: 0, target_pose: {x: 1, y: 2, yaw: 0}, rail_frame: {x: 1, y: 3, yaw: 0}}\n"
        << "  - {index: 1, target_pose: {x: 1, y: two, yaw: 0}, rail_frame: {x: 1, y: 3, yaw: 0}}\n";
  }
  RailSetFile loaded;
  std::string error;
  EXPECT_FALSE(loadRailSetFile(path, &loaded, &error));
  EXPECT_NE(error.find("rail_sets[1].target_pose"), std::string::npos) << error;
  EXPECT_FALSE(loadRailSetFile(path + ".missing", &loaded, &error));
  std::remove(path.c_str());
}

TEST(RailSetFile, HandWrittenSetWithoutStatusIsGoodAndAWrongStatusIsNamed) {
  const std::string path = ::testing::TempDir() + "/rail_sets_status_" + std::to_string(::getpid()) + ".yaml";
  {
    std::ofstream out(path);
    out << "frame_id: map\nheadland_edge: {start: [0, 0], end: [5, 0], into_rows: [0, 1]}\n"
        << "rail_sets:\n  - {index: 0, target_pose: {x: 1, y: 2, yaw: 0}, rail_frame: {x: 1, y: 3, yaw: 0}}\n"
        << "  - {index: 1, status: maybe, target_pose: {x: 1, y: 2, yaw: 0}, rail_frame: {x: 1, y: 3, yaw: 0}}\n";
  }
  RailSetFile loaded;
  std::string error;
  EXPECT_FALSE(loadRailSetFile(path, &loaded, &error));
  EXPECT_NE(error.find("rail_sets[1].status"), std::string::npos) << error;
  {
    std::ofstream out(path);
    out << "frame_id: map\nheadland_edge: {start: [0, 0], end: [5, 0], into_rows: [0, 1]}\n"
        << "rail_sets:\n  - {index: 0, target_pose: {x: 1, y: 2, yaw: 0}, rail_frame: {x: 1, y: 3, yaw: 0}}\n";
  }
  ASSERT_TRUE(loadRailSetFile(path, &loaded, &error)) << error;
  EXPECT_TRUE(loaded.rail_sets[0].good);
  std::remove(path.c_str());
}
