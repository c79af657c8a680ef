// Regression tests for maps that used to come out wrong while the analysis said "ok": a noise line taken
// for the rear wall, speckle across the side walls, clutter in line with a ventilation line, a wrong
// configured spacing, a missing side wall, and a PGM whose header claims a huge image.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "greenhouse_rail_nav/map_analyzer.h"
#include "thorvald_map/map_file.h"
#include "greenhouse_rail_nav/rail_spacing.h"
#include "greenhouse_rail_nav/testing/synthetic_greenhouse_map.h"

using namespace greenhouse_rail_nav;

namespace {

// What a mission needs: every set reported good is within 5 cm across and 0.5 degrees of a true one.
constexpr double kAcross = 0.05;
constexpr double kHeading = 0.5 * M_PI / 180.0;

double acrossError(const thorvald_base::Pose2D& est, const thorvald_base::Pose2D& tru) {
  return std::abs(-std::sin(tru.yaw) * (est.x - tru.x) + std::cos(tru.yaw) * (est.y - tru.y));
}

/// Every good set matches the true set with the same index (all true sets found), within tolerance.
void expectAllGoodAndRight(const SyntheticGreenhouseMap& truth, const MapAnalysis& result) {
  ASSERT_EQ(result.status, MapStatus::kOk) << result.message << " | " << result.uncertain_reasons;
  ASSERT_EQ(result.rail_sets.size(), truth.rail_frames.size()) << result.message;
  for (std::size_t i = 0; i < truth.rail_frames.size(); ++i) {
    const auto& set = result.rail_sets[i];
    EXPECT_TRUE(set.good) << i << ": " << set.reason;
    EXPECT_LT(acrossError(set.rail_frame, truth.rail_frames[i]), kAcross) << "rail set " << i;
    EXPECT_LT(std::abs(thorvald_base::normalizeAngle(set.rail_frame.yaw - truth.rail_frames[i].yaw)), kHeading)
        << "rail set " << i;
  }
}

/// Paints a thin line of cells (occupied unless told) between two layout-frame points.
void paintLine(thorvald_map::OccupancyGrid* map, const thorvald_base::Pose2D& layout_in_map, const Eigen::Vector2d& a,
               const Eigen::Vector2d& b, std::int8_t value = thorvald_map::kOccupied) {
  const double length = (b - a).norm();
  for (double s = 0.0; s <= length; s += 0.25 * map->resolution_m) {
    int c = 0, r = 0;
    if (map->worldToCell(layout_in_map.transformPoint(a + (b - a) * (s / length)), &c, &r)) map->at(c, r) = value;
  }
}

}  // namespace

TEST(MapRobustness, NoiseLineOnTheHeadlandIsNotTakenForTheRearWall) {
  for (const double yaw : {0.0, 1.2, -2.5}) {
    GreenhouseLayout layout;
    layout.rail_sets = 5;
    layout.visible_rows = {2, 3};
    layout.clutter_objects = 0;
    layout.layout_in_map = thorvald_base::Pose2D(1.0, 2.0, yaw);
    auto truth = makeGreenhouseMap(layout);
    // Decoys: a 2 m line parallel to the rear wall in the middle of the headland, and a 1.5 m line along
    // the rows near a side wall (either could pass for a wall with the rows on one side of it).
    paintLine(&truth.map, layout.layout_in_map, {3.0, 2.0}, {5.0, 2.0});
    paintLine(&truth.map, layout.layout_in_map, {0.8, 0.8}, {0.8, 2.3});
    SCOPED_TRACE(yaw);
    const auto result = analyzeMap(truth.map, MapAnalyzerParams());
    expectAllGoodAndRight(truth, result);
    const Eigen::Vector2d true_into_rows(std::cos(yaw + M_PI / 2), std::sin(yaw + M_PI / 2));
    EXPECT_GT(result.into_rows.dot(true_into_rows), 0.999);
  }
}

TEST(MapRobustness, SpeckleAcrossTheSideWallsAtFineResolution) {
  for (const double res : {0.05, 0.025}) {
    GreenhouseLayout layout;
    layout.rail_sets = 9;
    layout.resolution_m = res;
    layout.row_probability = 0.6;
    layout.speckle_free_fraction = 0.01;  // 1 % of the free cells
    layout.seed = 5;
    layout.layout_in_map = thorvald_base::Pose2D(0.0, 0.0, 0.3);
    const auto truth = makeGreenhouseMap(layout);
    SCOPED_TRACE(res);
    const auto result = analyzeMap(truth.map, MapAnalyzerParams());
    EXPECT_GT(result.speckle_cells_removed, 100u);
    EXPECT_TRUE(result.left_wall_found);
    EXPECT_TRUE(result.right_wall_found);
    expectAllGoodAndRight(truth, result);
  }
}

TEST(MapRobustness, ClutterInLineWithAVentilationLineDoesNotMoveTheEdge) {
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    GreenhouseLayout layout;
    layout.rail_sets = 6;
    layout.visible_rows = {2, 4};
    layout.ventilation_fraction = 1.0;
    layout.clutter_in_line = true;
    layout.clutter_objects = 0;
    layout.seed = seed;
    const auto truth = makeGreenhouseMap(layout);
    SCOPED_TRACE(seed);
    const auto result = analyzeMap(truth.map, MapAnalyzerParams());
    expectAllGoodAndRight(truth, result);
    // The edge is at the rows' start, not at the box in front of one of them.
    EXPECT_LT((result.edge_start - truth.edge_start).norm(), 0.1);
    EXPECT_LT((result.edge_end - truth.edge_end).norm(), 0.1);
  }
}

TEST(MapRobustness, SideWallsBehindDoorsDoNotSetTheHeadlandEdge) {
  // Doors at the same place in both side walls, near the rear wall: behind them each wall piece starts
  // like a row would, and together they outnumber the one row; they have no floor on their outer side, so
  // they are no rows.
  for (const double yaw : {0.0, 2.0, -1.0}) {
    GreenhouseLayout layout;
    layout.rail_sets = 4;
    layout.spacing_m = 1.5;
    layout.visible_rows = {2};
    layout.headland_depth_m = 5.0;
    layout.clutter_objects = 0;
    layout.layout_in_map = thorvald_base::Pose2D(0.5, 1.0, yaw);
    auto truth = makeGreenhouseMap(layout);
    const double width = layout.rail_sets * layout.spacing_m, res = layout.resolution_m;
    for (double d = 0.0; d <= layout.wall_thickness_m + res; d += 0.5 * res) {
      paintLine(&truth.map, layout.layout_in_map, {-d, 0.6}, {-d, 1.6}, thorvald_map::kUnknown);
      paintLine(&truth.map, layout.layout_in_map, {width + d, 0.6}, {width + d, 1.6}, thorvald_map::kUnknown);
    }
    SCOPED_TRACE(yaw);
    expectAllGoodAndRight(truth, analyzeMap(truth.map, MapAnalyzerParams()));
  }
}

TEST(MapRobustness, BoxesInFrontOfASideWallDoNotHideIt) {
  // Boxes between the side wall and the outermost row stop most of the scanlines across the headland before
  // the wall; with floor behind them they are walked through and the wall is still found.
  for (const double yaw : {0.0, 2.5}) {
    GreenhouseLayout layout;
    layout.rail_sets = 5;
    layout.visible_rows = {1, 2, 3, 4};
    layout.headland_depth_m = 4.0;
    layout.clutter_objects = 0;
    layout.layout_in_map = thorvald_base::Pose2D(1.0, 1.0, yaw);
    auto truth = makeGreenhouseMap(layout);
    for (const auto& box :
         {Eigen::Vector2d(0.1, 0.9), Eigen::Vector2d(1.2, 2.0), Eigen::Vector2d(2.3, 3.1), Eigen::Vector2d(3.4, 3.9)}) {
      for (double x = 0.3; x <= 1.1; x += 0.5 * layout.resolution_m)
        paintLine(&truth.map, layout.layout_in_map, {x, box.x()}, {x, box.y()});
    }
    SCOPED_TRACE(yaw);
    const auto result = analyzeMap(truth.map, MapAnalyzerParams());
    EXPECT_TRUE(result.left_wall_found) << result.message;
    expectAllGoodAndRight(truth, result);
  }
}

TEST(MapRobustness, ARowWhoseStartIsHiddenIsNamedNotAveragedIntoTheEdge) {
  // A narrow box just in front of one of five rows makes that row seem to start 0.3 m early; the edge and
  // its straightness come from the rows that agree, and the row is named in a warning.
  for (const double yaw : {0.3, -2.8}) {
    GreenhouseLayout layout;
    layout.rail_sets = 6;
    layout.visible_rows = {1, 2, 3, 4, 5};
    layout.ventilation_fraction = 1.0;
    layout.gap_probability = 0.0;
    layout.clutter_objects = 0;
    layout.layout_in_map = thorvald_base::Pose2D(1.0, 1.0, yaw);
    auto truth = makeGreenhouseMap(layout);
    const double x = 3 * layout.spacing_m, y1 = layout.headland_depth_m - 0.05;
    for (double dx = -0.1; dx <= 0.1; dx += 0.5 * layout.resolution_m)
      paintLine(&truth.map, layout.layout_in_map, {x + dx, y1 - 0.25}, {x + dx, y1});
    SCOPED_TRACE(yaw);
    const auto result = analyzeMap(truth.map, MapAnalyzerParams());
    expectAllGoodAndRight(truth, result);
    EXPECT_TRUE(std::any_of(result.warnings.begin(), result.warnings.end(), [](const std::string& w) {
      return w.find("off the headland edge") != std::string::npos;
    })) << result.message;
  }
}

TEST(MapRobustness, SpacingIsMeasuredNotTakenFromTheConfiguration) {
  GreenhouseLayout layout;
  layout.rail_sets = 16;
  layout.spacing_m = 1.8;
  layout.row_probability = 0.5;
  layout.seed = 9;
  const auto truth = makeGreenhouseMap(layout);
  MapAnalyzerParams params;
  params.rail_set_spacing_m = 1.60;  // the default, on a greenhouse of 1.8 m
  const auto result = analyzeMap(truth.map, params);
  expectAllGoodAndRight(truth, result);
  EXPECT_NEAR(result.spacing_m, 1.8, 0.02);
  bool warned = false;
  for (const auto& w : result.warnings) warned = warned || w.find("measured rail-set spacing") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(MapRobustness, MissingSideWallMarksTheOuterSetsUncertain) {
  GreenhouseLayout layout;
  layout.rail_sets = 7;
  layout.visible_rows = {2, 3, 5};
  layout.left_wall = false;
  layout.floor_beyond_missing_wall_m = 1.0;
  layout.rear_wall_ends_at_corner = false;  // nothing in the map says where the greenhouse ends on the left
  const auto truth = makeGreenhouseMap(layout);
  const auto result = analyzeMap(truth.map, MapAnalyzerParams());
  ASSERT_TRUE(result.ok) << result.message;
  EXPECT_EQ(result.status, MapStatus::kUncertain);
  EXPECT_TRUE(result.left_open);
  EXPECT_FALSE(result.left_wall_found);
  EXPECT_TRUE(result.right_wall_found);
  EXPECT_NE(result.uncertain_reasons.find("no left side wall"), std::string::npos) << result.uncertain_reasons;
  // Sets 0 and 1 (left of row 2) are uncertain; every good one is right.
  int good = 0;
  for (const auto& set : result.rail_sets) {
    if (!set.good) {
      EXPECT_NE(set.reason.find("no left side wall"), std::string::npos) << set.reason;
      continue;
    }
    ++good;
    double best = 1e9;
    for (const auto& t : truth.rail_frames) best = std::min(best, acrossError(set.rail_frame, t));
    EXPECT_LT(best, kAcross);
  }
  EXPECT_EQ(good, 5);  // sets 2..6
}

TEST(MapRobustness, TwoFarRowsWithoutWallsGiveAmbiguousSets) {
  // Two rows 6.4 m apart and no side walls: 4 sets of 1.6 m or 5 of 1.28 m both fit; nothing says which.
  GreenhouseLayout layout;
  layout.rail_sets = 8;
  layout.visible_rows = {2, 6};
  layout.side_walls = false;
  layout.floor_beyond_missing_wall_m = 0.0;
  const auto truth = makeGreenhouseMap(layout);
  const auto result = analyzeMap(truth.map, MapAnalyzerParams());
  ASSERT_TRUE(result.ok) << result.message;
  EXPECT_EQ(result.status, MapStatus::kUncertain);
  for (const auto& set : result.rail_sets) EXPECT_FALSE(set.good);
}

TEST(MapRobustness, MissingSideWallBoundedByTheRearWallsEnd) {
  // The left side wall is not in the map, but the rear wall ends at the corner with floor beyond: the two
  // sets left of row 2 lie between that row and the corner, placed by the rows' spacing.
  for (const double beyond : {0.4, 2.0}) {
    GreenhouseLayout layout;
    layout.rail_sets = 7;
    layout.visible_rows = {2, 3, 5};
    layout.left_wall = false;
    layout.floor_beyond_missing_wall_m = beyond;
    const auto truth = makeGreenhouseMap(layout);
    const auto result = analyzeMap(truth.map, MapAnalyzerParams());
    expectAllGoodAndRight(truth, result);
    EXPECT_FALSE(result.left_wall_found);
    EXPECT_TRUE(result.left_by_rear_wall_end);
    EXPECT_FALSE(result.left_open);
  }
}

TEST(MapRobustness, MissingSideWallWithTheRearWallEndingOffTheRowsPatternStaysOpen) {
  // The rear wall ends, with floor beyond, 0.8 m (half a spacing) past where the corner would be: no whole
  // number of spacings fits, so the sets beyond row 2 stay uncertain rather than guessed.
  GreenhouseLayout layout;
  layout.rail_sets = 7;
  layout.visible_rows = {2, 3, 5};
  layout.left_wall = false;
  layout.floor_beyond_missing_wall_m = 2.0;
  layout.rear_wall_ends_at_corner = false;
  auto truth = makeGreenhouseMap(layout);
  // Cut the rear wall 0.8 m beyond the corner (layout frame: x across, the corner at x = 0): floor there.
  const thorvald_base::Pose2D to_layout = layout.layout_in_map.inverse();
  for (int r = 0; r < truth.map.height; ++r) {
    for (int c = 0; c < truth.map.width; ++c) {
      const Eigen::Vector2d p = to_layout.transformPoint(truth.map.cellCentre(c, r));
      if (p.x() < -0.8 && p.y() < 0.0 && truth.map.at(c, r) == thorvald_map::kOccupied)
        truth.map.at(c, r) = thorvald_map::kUnknown;
    }
  }
  const auto result = analyzeMap(truth.map, MapAnalyzerParams());
  ASSERT_TRUE(result.ok) << result.message;
  EXPECT_EQ(result.status, MapStatus::kUncertain);
  EXPECT_FALSE(result.left_by_rear_wall_end);
  EXPECT_TRUE(result.left_open);
}

TEST(MapRobustness, TubeSeenFromOneSideIsPlacedAtItsCentre) {
  // Ventilation tubes 0.16 m wide; the one under row 3 is seen from its left path only (its right face
  // unknown but at its front). The cells' mean would put it 8 cm left of its centre: the sets beside it
  // 4 cm off, and the gaps no longer whole spacings.
  for (const double resolution : {0.025, 0.05}) {
    GreenhouseLayout layout;
    layout.rail_sets = 6;
    layout.resolution_m = resolution;
    layout.visible_rows = {1, 3, 4};
    layout.ventilation_fraction = 1.0;
    layout.ventilation_width_m = 0.16;
    layout.rows_seen_from_left_only = {3};
    layout.gap_probability = 0.0;
    const auto truth = makeGreenhouseMap(layout);
    const auto result = analyzeMap(truth.map, MapAnalyzerParams());
    expectAllGoodAndRight(truth, result);
    for (std::size_t i = 0; i < truth.rail_frames.size() && i < result.rail_sets.size(); ++i)
      EXPECT_LT(acrossError(result.rail_sets[i].rail_frame, truth.rail_frames[i]), 0.02) << resolution << " " << i;
  }
}

TEST(MapRobustness, FarEndWallIsNotTakenForTheRearWall) {
  // The wall at the rows' far end, seen through the paths 12 m beyond the mapped part of the rows, 0.6 m
  // longer than the rear wall and closing the same side walls and rows: the rear wall is the one the rows
  // are seen near (the map is made on the headland).
  GreenhouseLayout layout;
  layout.rail_sets = 5;
  layout.visible_rows = {1, 2, 4};
  layout.end_wall_gap_m = 12.0;
  const auto truth = makeGreenhouseMap(layout);
  const auto result = analyzeMap(truth.map, MapAnalyzerParams());
  expectAllGoodAndRight(truth, result);
}

TEST(MapRobustness, SideWallsOffSquareAreTakenWhereTheyMeetTheEdge) {
  // The whole greenhouse sheared: side walls and rows 8 mrad off square to the rear wall (a real
  // greenhouse, or its map). The walls' place at the edge, not their median over the headland, bounds the
  // outer sets (5 m of headland: 4 cm apart).
  GreenhouseLayout layout;
  layout.rail_sets = 4;
  layout.resolution_m = 0.025;
  layout.headland_depth_m = 5.0;
  layout.visible_rows = {1, 2, 3};
  auto truth = makeGreenhouseMap(layout);
  thorvald_map::OccupancyGrid sheared = truth.map;
  const thorvald_base::Pose2D to_layout = layout.layout_in_map.inverse();
  const double shear = 0.008;
  // Each cell takes the value the unsheared map has at x - shear * (y - headland depth) (layout frame).
  for (int r = 0; r < sheared.height; ++r) {
    for (int c = 0; c < sheared.width; ++c) {
      const Eigen::Vector2d p = to_layout.transformPoint(sheared.cellCentre(c, r));
      if (p.y() < 0.0) continue;  // the rear wall stays
      const Eigen::Vector2d q(p.x() - shear * (p.y() - layout.headland_depth_m), p.y());
      sheared.at(c, r) = truth.map.valueAt(layout.layout_in_map.transformPoint(q));
    }
  }
  const auto result = analyzeMap(sheared, MapAnalyzerParams());
  ASSERT_TRUE(result.ok) << result.message;
  ASSERT_EQ(result.rail_sets.size(), 4u) << result.message;
  // The walls' inner faces where they meet the edge, across the greenhouse (map x here): the true edge's
  // ends (the median over the headland is 2-2.5 cm off). Within half a cell and the sampling.
  ASSERT_TRUE(result.left_wall_found && result.right_wall_found);
  EXPECT_LT(std::abs((result.left_wall - truth.edge_start).x()), 0.012) << result.left_wall.transpose();
  EXPECT_LT(std::abs((result.right_wall - truth.edge_end).x()), 0.012) << result.right_wall.transpose();
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(result.rail_sets[i].good) << i << ": " << result.rail_sets[i].reason;
    EXPECT_LT(acrossError(result.rail_sets[i].rail_frame, truth.rail_frames[i]), 0.02) << i;
  }
}

TEST(MapRobustness, EveryResultCarriesItsChecks) {
  GreenhouseLayout layout;
  layout.rail_sets = 6;
  layout.visible_rows = {1, 3, 5};
  const auto result = analyzeMap(makeGreenhouseMap(layout).map, MapAnalyzerParams());
  ASSERT_EQ(result.status, MapStatus::kOk) << result.uncertain_reasons;
  EXPECT_NEAR(result.confidence, 1.0, 1e-9);
  std::vector<std::string> names;
  for (const auto& c : result.checks) {
    names.push_back(c.name);
    EXPECT_TRUE(c.passed) << c.name;
  }
  for (const char* expected : {"edge_straight", "rows_agree_in_heading", "spacing_regular", "spacing_unambiguous",
                               "sides_bounded", "rear_wall_spans_rows"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
}

TEST(MapRobustness, HugePgmHeaderIsRefusedWithTheSize) {
  const std::string base = ::testing::TempDir() + "/greenhouse_rail_nav_huge_" + std::to_string(::getpid());
  {
    std::ofstream pgm(base + ".pgm", std::ios::binary);
    pgm << "P5\n# comment\n100000 50000\n255\n";
    pgm.write("\0\0\0\0", 4);
    std::ofstream yaml(base + ".yaml");
    yaml << "image: " << base << ".pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
         << "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  }
  thorvald_map::OccupancyGrid map;
  std::string error;
  EXPECT_FALSE(thorvald_map::loadMap(base + ".yaml", &map, &error));
  EXPECT_NE(error.find("100000 x 50000"), std::string::npos) << error;
  // A small limit refuses an ordinary map too, naming both sizes.
  {
    std::ofstream pgm(base + ".pgm", std::ios::binary);
    pgm << "P5\n30 20\n255\n" << std::string(600, '\xfe');
  }
  EXPECT_TRUE(thorvald_map::loadMap(base + ".yaml", &map, &error)) << error;
  thorvald_map::MapLoadOptions small;
  small.max_cells = 500;
  EXPECT_FALSE(thorvald_map::loadMap(base + ".yaml", &map, &error, small));
  EXPECT_NE(error.find("30 x 20"), std::string::npos) << error;
  std::remove((base + ".pgm").c_str());
  std::remove((base + ".yaml").c_str());
}

TEST(RailSpacing, RegularGapsGiveOneUnambiguousSpacing) {
  const auto est = estimateSpacing({1.81, 3.59, 1.79, 5.42}, 1.6, 1.3, 0.08);
  EXPECT_TRUE(est.regular);
  EXPECT_EQ(est.hypotheses, 1);
  EXPECT_NEAR(est.spacing_m, 1.8, 0.01);
  EXPECT_EQ(est.sets_per_gap, (std::vector<int>{1, 2, 1, 3}));
}

TEST(RailSpacing, ABadGapIsMarkedAndDoesNotSpoilTheRest) {
  const auto est = estimateSpacing({1.6, 1.6, 0.95, 2.25, 1.6, 3.2}, 1.6, 1.3, 0.08);
  EXPECT_FALSE(est.regular);
  EXPECT_NEAR(est.spacing_m, 1.6, 0.01);
  EXPECT_TRUE(est.gap_fits[0]);
  EXPECT_FALSE(est.gap_fits[2]);
  EXPECT_FALSE(est.gap_fits[3]);
  EXPECT_TRUE(est.gap_fits[5]);
}

TEST(RailSpacing, OneWideGapIsAmbiguous) {
  const auto est = estimateSpacing({6.4}, 1.6, 1.3, 0.08);
  EXPECT_GT(est.hypotheses, 1);
  EXPECT_TRUE(est.gap_ambiguous[0]);
  EXPECT_EQ(est.sets_per_gap[0], 4);  // nearest the configured spacing
}
