// The stages of analyzeMap after the rows are found, each on hand-made inputs (no map needed).
#include <gtest/gtest.h>

#include <cmath>

#include "greenhouse_rail_nav/map_analysis_stages.h"

namespace greenhouse_rail_nav {
namespace {

EdgeRow row(double u, double start_v = NAN) {
  EdgeRow r;
  r.u = u;
  r.start_v = start_v;
  r.d_min = -0.1;
  r.d_max = 0.1;
  r.fit.direction = Eigen::Vector2d::UnitY();
  r.fit.s_min = 0.0;
  r.fit.s_max = 10.0;
  return r;
}

SideScan noWall(double floor_extent_m) {
  SideScan s;
  s.floor_extent_m = floor_extent_m;
  return s;
}

SpacingFit regularFit(double spacing_m) {
  SpacingFit fit;
  fit.gaps = {spacing_m, spacing_m};
  fit.spacing_m = spacing_m;
  fit.fit_tolerance_m = 0.08;
  fit.estimate.regular = true;
  fit.estimate.hypotheses = 1;
  fit.estimate.spacing_m = spacing_m;
  return fit;
}

TEST(MapAnalysisStages, HeadlandFrameLooksIntoTheRowsWithURight) {
  LineFit2D wall;
  wall.centroid = {2.0, 1.0};
  wall.direction = Eigen::Vector2d::UnitX();
  const HeadlandFrame f = headlandFrameOf(wall, -1.0);
  EXPECT_NEAR(f.v.x(), 0.0, 1e-12);
  EXPECT_NEAR(f.v.y(), -1.0, 1e-12);
  EXPECT_NEAR(f.u.x(), -1.0, 1e-12);  // (v.y, -v.x): right of v
  EXPECT_NEAR(f.u.y(), 0.0, 1e-12);
  EXPECT_NEAR((f.toMap(0.0, 0.0) - wall.centroid).norm(), 0.0, 1e-12);
}

TEST(MapAnalysisStages, OuterLineWithoutFloorBeyondIsTheSideWall) {
  std::vector<EdgeRow> rows = {row(0.0), row(1.6), row(3.2)};
  SideScan left = noWall(0.1), right = noWall(2.0);
  takeOuterLinesAsSideWalls(&left, &right, &rows);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_TRUE(left.wall_found);
  EXPECT_DOUBLE_EQ(left.wall_u, 0.1);  // the inner face: u + d_max
  EXPECT_FALSE(right.wall_found);
  EXPECT_DOUBLE_EQ(rows.front().u, 1.6);
}

TEST(MapAnalysisStages, LastRowIsNeverTakenAsAWall) {
  std::vector<EdgeRow> rows = {row(0.0), row(1.6)};
  SideScan left = noWall(0.0), right = noWall(0.0);
  takeOuterLinesAsSideWalls(&left, &right, &rows);
  EXPECT_EQ(rows.size(), 1u);  // the left went, the right must stay: one row remains
  EXPECT_TRUE(left.wall_found);
  EXPECT_FALSE(right.wall_found);
  SideScan found;
  found.wall_found = true;
  found.wall_u = -1.0;
  std::vector<EdgeRow> two = {row(0.0), row(1.6)};
  SideScan right2 = noWall(5.0);
  takeOuterLinesAsSideWalls(&found, &right2, &two);
  EXPECT_EQ(two.size(), 2u);  // a wall already found is kept
  EXPECT_DOUBLE_EQ(found.wall_u, -1.0);
}

TEST(MapAnalysisStages, EdgeStraightnessNamesLateStartsAndSkipsUnseenOnes) {
  const std::vector<EdgeRow> rows = {row(0.0, 2.03), row(1.6, 1.97), row(3.2, 2.5), row(4.8)};
  std::vector<std::string> warnings;
  const EdgeStraightness e = measureEdgeStraightness(rows, 2.0, 0.1, &warnings);
  EXPECT_EQ(e.rows_at_edge, 2);
  EXPECT_NEAR(e.rms_m, 0.03, 1e-9);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "row at 3.20 m starts 0.50 m off the headland edge");
  EXPECT_TRUE(std::isinf(measureEdgeStraightness({row(0.0)}, 2.0, 0.1, &warnings).rms_m));
}

TEST(MapAnalysisStages, RowHeadingToleranceGrowsForShortRows) {
  std::vector<EdgeRow> rows = {row(0.0), row(1.6), row(3.2)};
  const double tilt = 0.03;  // 10 m long: 0.02 + 0.05 / 10 = 0.025 rad allowed
  rows[1].fit.direction = Eigen::Vector2d(std::sin(tilt), std::cos(tilt));
  EXPECT_EQ(judgeRowHeadings(&rows, Eigen::Vector2d::UnitY(), 0.05, 0.02), 1);
  EXPECT_FALSE(rows[1].heading_ok);
  EXPECT_TRUE(rows[0].heading_ok);
  rows[1].fit.s_max = 2.0;  // 2 m long: 0.02 + 0.05 / 2 = 0.045 rad allowed
  EXPECT_EQ(judgeRowHeadings(&rows, Eigen::Vector2d::UnitY(), 0.05, 0.02), 0);
  EXPECT_TRUE(rows[1].heading_ok);
}

TEST(MapAnalysisStages, SetsToTheRearWallEndAreWholeSpacingsPlusAtMostAWall) {
  const SpacingFit fit = regularFit(1.6);
  RearWallEnd end;
  end.usable = true;
  end.distance = 3.2 + 0.3;  // two sets and a 0.3 m wall
  EXPECT_EQ(setsToRearWallEnd(end, fit, true, 0.35), 2);
  end.distance = 3.2 + 0.5;  // the remainder is no wall
  EXPECT_EQ(setsToRearWallEnd(end, fit, true, 0.35), -1);
  end.distance = 3.2 - 0.05;  // within the fit tolerance short of two spacings
  EXPECT_EQ(setsToRearWallEnd(end, fit, true, 0.35), 2);
  end.distance = 1.0;  // not even one set
  EXPECT_EQ(setsToRearWallEnd(end, fit, true, 0.35), -1);
  end.distance = 3.2;
  EXPECT_EQ(setsToRearWallEnd(end, fit, false, 0.35), -1);  // spacing not confirmed
  SpacingFit ambiguous = fit;
  ambiguous.estimate.hypotheses = 2;
  EXPECT_EQ(setsToRearWallEnd(end, ambiguous, true, 0.35), -1);
  end.usable = false;
  EXPECT_EQ(setsToRearWallEnd(end, fit, true, 0.35), -1);
}

TEST(MapAnalysisStages, SidesBoundedByWallOrRearWallEnd) {
  const SpacingFit fit = regularFit(1.6);
  SideScan left;
  left.wall_found = true;
  const SideScan right = noWall(5.0);
  RearWallEnd right_end;
  right_end.usable = true;
  right_end.end_u = 8.0;
  right_end.distance = 1.6 + 0.2;
  MapAnalysis result;
  const SideBounds b = boundSides(left, right, RearWallEnd(), right_end, fit, true, 0.35, &result);
  EXPECT_EQ(b.left_end_sets, -1);
  EXPECT_EQ(b.right_end_sets, 1);
  EXPECT_FALSE(result.left_by_rear_wall_end);
  EXPECT_TRUE(result.right_by_rear_wall_end);
  ASSERT_EQ(result.checks.size(), 1u);
  EXPECT_EQ(result.checks[0].name, "sides_bounded");
  EXPECT_TRUE(result.checks[0].passed);
  EXPECT_NE(result.checks[0].detail.find("(left: wall, right: rear wall's end)"), std::string::npos);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_NE(result.warnings[0].find("no right side wall found: the rear wall's end at 8.00 m"), std::string::npos);

  MapAnalysis open;
  boundSides(noWall(5.0), right, RearWallEnd(), RearWallEnd(), fit, true, 0.35, &open);
  EXPECT_FALSE(open.checks[0].passed);
  EXPECT_DOUBLE_EQ(open.checks[0].value, 0.0);
}

TEST(MapAnalysisStages, SpacingFitOrdersWallsAndRows) {
  SideScan left, right;
  left.wall_found = right.wall_found = true;
  left.wall_u = -1.6;
  right.wall_u = 3.2;
  MapAnalyzerParams params;
  const SpacingFit fit = fitSpacing(left, {row(0.0), row(1.6)}, right, params, 0.05);
  ASSERT_EQ(fit.bounds.size(), 4u);
  EXPECT_EQ(fit.bounds.front().name, "left side wall");
  EXPECT_EQ(fit.bounds[1].name, "row at 0.00 m");
  ASSERT_EQ(fit.gaps.size(), 3u);
  EXPECT_NEAR(fit.spacing_m, 1.6, 1e-9);
  EXPECT_DOUBLE_EQ(fit.fit_tolerance_m, 0.08);  // max(0.08, 1.5 * 0.05)
  const SpacingFit none = fitSpacing(SideScan(), {row(0.0)}, SideScan(), params, 0.1);
  EXPECT_TRUE(none.gaps.empty());
  EXPECT_DOUBLE_EQ(none.spacing_m, params.rail_set_spacing_m);  // the configured one without a gap
  EXPECT_NEAR(none.fit_tolerance_m, 0.15, 1e-12);
}

TEST(MapAnalysisStages, RailSetsAreGoodOnlyWithoutAnyReason) {
  HeadlandFrame frame;
  std::vector<RailSetPlan> plans = {{0.8, {}}, {2.4, {"gap does not fit"}}};
  MapAnalysis result;
  const int good = placeRailSets(plans, frame, 2.0, M_PI / 2, thorvald_base::Pose2D(-0.8, 0.0, 0.0), {}, &result);
  EXPECT_EQ(good, 1);
  ASSERT_EQ(result.rail_sets.size(), 2u);
  EXPECT_EQ(result.rail_sets[1].index, 1);
  EXPECT_EQ(result.rail_sets[1].reason, "gap does not fit");
  EXPECT_NEAR(result.rail_sets[0].rail_frame.x, 0.8, 1e-12);
  EXPECT_NEAR(result.rail_sets[0].target_pose.y, 2.0 - 0.8, 1e-12);  // 0.8 m back along the heading (+y)
  MapAnalysis global;
  EXPECT_EQ(placeRailSets(plans, frame, 2.0, 0.0, {}, {"edge", "heading"}, &global), 0);
  EXPECT_EQ(global.rail_sets[1].reason, "edge; heading; gap does not fit");
}

TEST(MapAnalysisStages, JudgementFromChecksAndSets) {
  const SpacingFit fit = regularFit(1.6);
  MapAnalysis none;
  none.checks.push_back({"a", true, 0, 0, ""});
  judgeAnalysis(0, 0, {}, fit, &none);
  EXPECT_EQ(none.status, MapStatus::kFailed);
  EXPECT_DOUBLE_EQ(none.confidence, 0.0);

  MapAnalysis r;
  r.checks = {{"a", true, 0, 0, ""}, {"b", false, 0, 0, ""}};
  r.rail_sets.resize(2);
  judgeAnalysis(1, 0, {}, fit, &r);
  EXPECT_TRUE(r.ok);
  EXPECT_EQ(r.status, MapStatus::kUncertain);
  EXPECT_DOUBLE_EQ(r.confidence, 0.5 * 0.5);
  EXPECT_EQ(r.uncertain_reasons, "failed checks: b");  // no reason of its own: the failed checks

  MapAnalysis open;
  open.checks = {{"a", true, 0, 0, ""}};
  open.rail_sets.resize(1);
  open.left_open = true;
  judgeAnalysis(1, 2, {"edge"}, fit, &open);
  EXPECT_EQ(open.status, MapStatus::kOk);  // every check passed and every set good
  EXPECT_TRUE(open.uncertain_reasons.empty());
  open.checks[0].passed = false;
  judgeAnalysis(1, 2, {"edge"}, fit, &open);
  EXPECT_EQ(open.uncertain_reasons,
            "edge; 2 rows disagree in heading with the others; no left side wall found: rail sets may go on beyond "
            "the leftmost row");
}

TEST(MapAnalysisStages, IrregularGapsAreNamed) {
  SpacingFit fit = regularFit(1.6);
  fit.gaps = {1.6, 2.0};
  fit.bounds = {{0.0, "left side wall", true}, {1.6, "row at 1.60 m", true}, {3.6, "right side wall", true}};
  fit.estimate.regular = false;
  fit.estimate.gap_fits = {true, false};
  fit.estimate.gap_ambiguous = {false, false};
  MapAnalysis r;
  r.checks = {{"spacing_regular", false, 0, 0, ""}};
  r.rail_sets.resize(1);
  judgeAnalysis(1, 0, {}, fit, &r);
  EXPECT_EQ(r.uncertain_reasons, "gap of 2.00 m between row at 1.60 m and right side wall does not fit the spacing");
}

TEST(MapAnalysisStages, HeadingWeighsTheRowsAgainstTheRearWall) {
  LineSegment wall;
  wall.fit.direction = Eigen::Vector2d::UnitX();
  wall.fit.s_min = -5.0;
  wall.fit.s_max = 5.0;
  const HeadlandFrame frame = headlandFrameOf(wall.fit, 1.0);
  std::vector<EdgeRow> rows = {row(0.0), row(1.6)};
  for (auto& r : rows) {
    r.direction = Eigen::Vector2d(std::sin(0.01), std::cos(0.01));
    r.direction_sigma = 1e-6;  // far surer than the wall: the heading is the rows'
  }
  const double h =
      greenhouseHeading({wall}, 0, frame, rows, Eigen::Vector2d::UnitY(), SideScan(), SideScan(), 2.0, 0.08, 0.05);
  EXPECT_NEAR(h, M_PI / 2 - 0.01, 1e-6);
  for (auto& r : rows) r.direction_sigma = INFINITY;  // rows without a direction: the wall's normal alone
  EXPECT_NEAR(
      greenhouseHeading({wall}, 0, frame, rows, Eigen::Vector2d::UnitY(), SideScan(), SideScan(), 2.0, 0.08, 0.05),
      M_PI / 2, 1e-12);
}

}  // namespace
}  // namespace greenhouse_rail_nav
