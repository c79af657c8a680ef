// rostest of map_analyzer: started by its launch file, fed a map file and maps on `map`.
#include <cmath>
#include <fstream>

#include <geometry_msgs/PolygonStamped.h>
#include <geometry_msgs/PoseArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <thorvald_common/ros/wait_for.h>
#include <std_msgs/String.h>
#include <visualization_msgs/MarkerArray.h>

#include "thorvald_map/ros/conversions.h"
#include "greenhouse_rail_nav/rail_set_file.h"
#include "greenhouse_rail_nav/testing/synthetic_greenhouse_map.h"

using namespace greenhouse_rail_nav;

namespace {

/// Keeps the last message of a topic and how many arrived.
template <typename M>
struct Latest {
  Latest(ros::NodeHandle& nh, const std::string& topic) {
    sub = nh.subscribe<M>(topic, 5, [this](const typename M::ConstPtr& m) {
      last = m;
      ++count;
    });
  }
  ros::Subscriber sub;
  typename M::ConstPtr last;
  int count = 0;
};

/// Spins until the condition holds or the deadline (wall time) passes.
template <typename F>
bool waitFor(F condition, double timeout_s = 20.0) {
  return thorvald_common::waitFor(condition, timeout_s);
}

// Targets compared with the truth: 7 cm (a little over one 5 cm cell), 0.02 rad.
void expectTargets(const geometry_msgs::PoseArray& targets, const SyntheticGreenhouseMap& truth) {
  ASSERT_EQ(targets.poses.size(), truth.rail_frames.size());
  for (std::size_t i = 0; i < truth.rail_frames.size(); ++i) {
    const thorvald_base::Pose2D expected = truth.rail_frames[i] * thorvald_base::Pose2D(-0.8, 0.0, 0.0);
    const auto& p = targets.poses[i];
    EXPECT_LT(std::hypot(p.position.x - expected.x, p.position.y - expected.y), 0.07) << i;
    EXPECT_LT(std::abs(thorvald_base::normalizeAngle(thorvald_map::yawOf(p.orientation) - expected.yaw)), 0.02) << i;
  }
}

}  // namespace

TEST(MapAnalyzerNode, AnalysesAMapFile) {
  ros::NodeHandle nh;
  Latest<geometry_msgs::PoseArray> targets(nh, "file/rail_targets");
  Latest<nav_msgs::OccupancyGrid> keep_out(nh, "file/keep_out_map");
  Latest<geometry_msgs::PolygonStamped> edge(nh, "file/headland_edge");
  Latest<visualization_msgs::MarkerArray> markers(nh, "file/map_analyzer/markers");
  ASSERT_TRUE(waitFor([&] { return targets.count && keep_out.count && edge.count && markers.count; }));
  // The file was written from this layout (test/data/headland.yaml).
  GreenhouseLayout layout;
  layout.rail_sets = 8;
  layout.visible_rows = {2, 5, 6};
  layout.seed = 77;
  const auto truth = makeGreenhouseMap(layout);
  expectTargets(*targets.last, truth);
  EXPECT_EQ(targets.last->header.frame_id, "map");
  EXPECT_EQ(keep_out.last->info.width, static_cast<unsigned>(truth.map.width));
  EXPECT_EQ(keep_out.last->info.height, static_cast<unsigned>(truth.map.height));
  ASSERT_EQ(edge.last->polygon.points.size(), 2u);
  EXPECT_NEAR(edge.last->polygon.points[0].x, truth.edge_start.x(), 0.1);
  EXPECT_NEAR(edge.last->polygon.points[1].y, truth.edge_end.y(), 0.1);
  EXPECT_GT(markers.last->markers.size(), 8u);
}

TEST(MapAnalyzerNode, AnalysesMapsOnTheTopicAndNeverInventsPoses) {
  ros::NodeHandle nh, pnh("~");
  std::string output_file;
  ASSERT_TRUE(pnh.getParam("output_file", output_file));
  Latest<geometry_msgs::PoseArray> targets(nh, "topic/rail_targets");
  Latest<std_msgs::String> status(nh, "topic/map_analyzer/status");
  ros::Publisher map_pub = nh.advertise<nav_msgs::OccupancyGrid>("topic/map", 1, true);
  ASSERT_TRUE(waitFor([&] { return map_pub.getNumSubscribers() > 0; }));

  // A rotated greenhouse with 11 rail sets.
  GreenhouseLayout rotated;
  rotated.rail_sets = 11;
  rotated.visible_rows = {1, 4, 8, 9};
  rotated.layout_in_map = thorvald_base::Pose2D(4.0, -2.0, 2.2);
  const auto truth = makeGreenhouseMap(rotated);
  map_pub.publish(thorvald_map::toGridMessage(truth.map, "map", ros::Time::now()));
  ASSERT_TRUE(waitFor([&] { return targets.count >= 1 && status.count >= 1; }));
  expectTargets(*targets.last, truth);
  EXPECT_EQ(status.last->data.rfind("ok:", 0), 0u) << status.last->data;
  RailSetFile file;
  std::string error;
  ASSERT_TRUE(loadRailSetFile(output_file, &file, &error)) << error;
  EXPECT_EQ(file.rail_sets.size(), 11u);

  // A single row: the side walls and the row give all 6 sets.
  GreenhouseLayout single;
  single.rail_sets = 6;
  single.visible_rows = {2};
  const auto single_truth = makeGreenhouseMap(single);
  map_pub.publish(thorvald_map::toGridMessage(single_truth.map, "map", ros::Time::now()));
  ASSERT_TRUE(waitFor([&] { return targets.count >= 2 && status.count >= 2; }));
  expectTargets(*targets.last, single_truth);

  // No rows: an empty PoseArray, and the status says what was found and what was expected.
  GreenhouseLayout bare;
  bare.rail_sets = 6;
  bare.row_probability = 0.0;
  map_pub.publish(thorvald_map::toGridMessage(makeGreenhouseMap(bare).map, "map", ros::Time::now()));
  ASSERT_TRUE(waitFor([&] { return targets.count >= 3 && status.count >= 3; }));
  EXPECT_TRUE(targets.last->poses.empty());
  EXPECT_EQ(status.last->data.rfind("failed:", 0), 0u) << status.last->data;
  EXPECT_NE(status.last->data.find("expected"), std::string::npos);

  // A malformed map (data shorter than width x height) is rejected; the node lives on.
  nav_msgs::OccupancyGrid bad = thorvald_map::toGridMessage(single_truth.map, "map", ros::Time::now());
  bad.data.resize(10);
  map_pub.publish(bad);
  ASSERT_TRUE(waitFor([&] { return status.count >= 4; }));
  EXPECT_NE(status.last->data.find("rejected"), std::string::npos) << status.last->data;
  map_pub.publish(thorvald_map::toGridMessage(single_truth.map, "map", ros::Time::now()));
  ASSERT_TRUE(waitFor([&] { return targets.count >= 4; }));
  EXPECT_EQ(targets.last->poses.size(), 6u);

  // A greenhouse without its left side wall in the map: the sets left of the outermost row are uncertain.
  // They are left out of rail_targets, published on rail_targets_uncertain, and marked in the file; the
  // status says uncertain and why; the overlay PNG is written.
  Latest<geometry_msgs::PoseArray> uncertain(nh, "topic/rail_targets_uncertain");
  GreenhouseLayout open_left;
  open_left.rail_sets = 7;
  open_left.visible_rows = {2, 3, 5};
  open_left.left_wall = false;
  open_left.rear_wall_ends_at_corner = false;
  const auto open_truth = makeGreenhouseMap(open_left);
  const int before = targets.count;
  map_pub.publish(thorvald_map::toGridMessage(open_truth.map, "map", ros::Time::now()));
  ASSERT_TRUE(waitFor([&] { return targets.count > before && uncertain.count >= 1; }));
  ASSERT_TRUE(waitFor([&] { return status.last->data.rfind("uncertain:", 0) == 0u; })) << status.last->data;
  EXPECT_NE(status.last->data.find("no left side wall"), std::string::npos) << status.last->data;
  EXPECT_EQ(targets.last->poses.size(), 5u);
  EXPECT_GE(uncertain.last->poses.size(), 1u);
  ASSERT_TRUE(loadRailSetFile(output_file, &file, &error)) << error;
  EXPECT_EQ(file.status, "uncertain");
  int good = 0;
  for (const auto& set : file.rail_sets) {
    good += set.good;
    if (!set.good) EXPECT_FALSE(set.reason.empty());
  }
  EXPECT_EQ(good, 5);
  std::string overlay;
  ASSERT_TRUE(pnh.getParam("overlay_png", overlay));
  std::ifstream png(overlay, std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG") << overlay;
  std::remove(output_file.c_str());
  std::remove(overlay.c_str());
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "map_analyzer_node_test");
  return RUN_ALL_TESTS();
}
