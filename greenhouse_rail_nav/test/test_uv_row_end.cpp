// The UV mission's run to a row's end of known length (rail_run.h): where the robot stops, the speed to get there
// with the far wall as a guard, and the share of the row the lamps lit.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "greenhouse_rail_nav/rail_run.h"
#include "simulated_greenhouse.h"

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Drives base_link from `from` to `to` along the row in 1 cm steps with the lights on where on(s).
template <typename On>
void drive(grn::RowLitCoverage* row, double from, double to, On on) {
  for (double s = from; s < to - 1e-12; s += 0.01) row->add(s, std::min(to, s + 0.01), on(s));
}

}  // namespace

TEST(RowEnd, StopsWhereTheDriveWheelsStillStandOnThePipes) {
  grn::RailRunParams p;  // placeholder lamps: lit from 0.70 m behind the axle to 0.05 m ahead of it
  EXPECT_DOUBLE_EQ(grn::rowStopPosition(p, 5.0), 5.0 - p.rail_end_margin_m);
  EXPECT_DOUBLE_EQ(grn::rowStopPosition(p, 20.0), 20.0 - p.rail_end_margin_m);
  // Lamps wholly ahead of the axle (from 0.75 m to 1.25 m): stop once their rear edge has passed the row's end.
  p.lamp_offset_m = 1.0;
  p.lamp_length_m = 0.5;
  EXPECT_DOUBLE_EQ(grn::rowStopPosition(p, 5.0), 5.0 - 0.75);
}

TEST(RowEnd, TreatmentSpeedUntilTheBrakingDistanceToTheStop) {
  grn::RailRunParams p;
  const double stop = grn::rowStopPosition(p, 5.0);
  EXPECT_DOUBLE_EQ(grn::inboundSpeedToRowEnd(p, 0.5, 1.0, 5.0, kNaN, 0.02), 0.5);
  EXPECT_NEAR(grn::inboundSpeedToRowEnd(p, 0.0, 1.0, 5.0, kNaN, 0.02), 0.01, 1e-12);  // ramps up
  const double d = 0.1;                                                               // braking: sqrt(2 a d)
  EXPECT_NEAR(grn::inboundSpeedToRowEnd(p, 0.5, stop - d, 5.0, kNaN, 0.02), std::sqrt(2.0 * p.accel_mps2 * d), 1e-12);
  EXPECT_EQ(grn::inboundSpeedToRowEnd(p, 0.1, stop, 5.0, kNaN, 0.02), 0.0);
  EXPECT_EQ(grn::inboundSpeedToRowEnd(p, 0.1, stop + 0.05, 5.0, kNaN, 0.02), 0.0);
  // The far wall seen where it agrees with the row: no effect until its guard range.
  EXPECT_DOUBLE_EQ(grn::inboundSpeedToRowEnd(p, 0.5, 1.0, 5.0, 4.5, 0.02), 0.5);
}

TEST(RowEnd, TheWallGuardStopsShortOfTheRowsEnd) {
  grn::RailRunParams p;
  EXPECT_EQ(grn::inboundSpeedToRowEnd(p, 0.5, 3.0, 5.0, p.wall_guard_range_m, 0.02), 0.0);
  EXPECT_EQ(grn::inboundSpeedToRowEnd(p, 0.5, 3.0, 5.0, p.wall_guard_range_m - 0.1, 0.02), 0.0);
  EXPECT_NEAR(grn::inboundSpeedToRowEnd(p, 0.5, 3.0, 5.0, p.wall_guard_range_m + 0.04, 0.02),
              std::sqrt(2.0 * p.accel_mps2 * 0.04), 1e-12);
}

TEST(RowLit, CountsTheRowUnderTheLampsNotWhatWasDriven) {
  grn::RailRunParams p;
  grn::RowLitCoverage all(p, 5.0);
  drive(&all, 0.2, grn::rowStopPosition(p, 5.0), [](double) { return true; });
  EXPECT_NEAR(all.fraction(), 1.0, 1e-9);  // from 0.2 - 0.7 < 0 to 4.92 + 0.05 (the last bin touched)

  grn::RowLitCoverage none(p, 5.0);
  drive(&none, 0.2, 4.92, [](double) { return false; });
  EXPECT_DOUBLE_EQ(none.fraction(), 0.0);

  // Driven half way with the lights on: half the row (up to the lamps' front edge), whatever was driven.
  grn::RowLitCoverage half(p, 5.0);
  drive(&half, 0.2, 2.45, [](double) { return true; });
  EXPECT_NEAR(half.fraction(), 0.5, 1e-9);

  // The wall guard 0.5 m short of the stop: the last 0.5 m stay dark.
  grn::RowLitCoverage short_(p, 5.0);
  drive(&short_, 0.2, grn::rowStopPosition(p, 5.0) - 0.5, [](double) { return true; });
  EXPECT_NEAR(short_.fraction(), (5.0 - 0.03 - 0.5) / 5.0, 0.011);
  EXPECT_LT(short_.fraction(), 0.99);

  // A gap with the lights off in the middle, then lit on: the gap stays counted out.
  grn::RowLitCoverage gap(p, 5.0);
  drive(&gap, 0.2, 4.92, [](double s) { return s < 2.0 || s > 3.0; });
  EXPECT_NEAR(gap.fraction(), 1.0 - (3.0 - 0.7 - 2.05) / 5.0, 0.011);
}

TEST(RowLit, AnEmptyRowIsLit) {
  grn::RowLitCoverage row(grn::RailRunParams{}, 0.0);
  row.add(0.0, 1.0, true);
  EXPECT_DOUBLE_EQ(row.fraction(), 1.0);
}

TEST(RowEnd, ParametersAreChecked) {
  grn::RailRunParams p;
  EXPECT_TRUE(p.validate().empty()) << p.validate();
  p.wall_guard_range_m = 0.0;
  p.lamp_length_m = -1.0;
  p.rail_end_margin_m = -0.1;
  const std::string e = p.validate();
  EXPECT_NE(e.find("wall_guard_range"), std::string::npos) << e;
  EXPECT_NE(e.find("lamp_length"), std::string::npos) << e;
  EXPECT_NE(e.find("rail_end_margin"), std::string::npos) << e;
}

// The mission's run to the row's end against the simulated greenhouse robot.
// The set's length known: the lamps light the row to its end; the drive axle stops rail_end_margin short of the rails'
// end (the lamps' front edge 3 cm short of it), and the lit share counts the row, not what was driven.
TEST(UvMissionRowEnd, LightsStayOnUntilTheLampsHaveLitTheRowToItsEnd) {
  const std::vector<RailSetTruth> sets = {{0.0}};
  SimulatedGreenhouse world(sets, 4);
  world.rail_length = 5.0;
  world.wall_past_end = 2.0;  // the guard out of the way (1 m: it stops the robot about as early, see below)
  grn::UvMissionParams p;
  auto targets = targetsFor(sets, -1.2);
  targets[0].rail_length_m = world.rail_length;
  grn::UvMission mission(world, p, targets);
  EXPECT_EQ(mission.run(), "done");
  ASSERT_EQ(mission.reports().size(), 1u);
  const grn::RailSetReport& r = mission.reports()[0];
  EXPECT_TRUE(r.treated) << r.result;
  EXPECT_GE(r.lit_pct, 99.0);
  const double stop = world.rail_length - p.rail_run.rail_end_margin_m;
  // This world's detector places the rails' start with 2 cm of noise in x: the stop by odometry from it as much.
  EXPECT_NEAR(world.last_lights_off_x, stop, 0.07) << "lights off where the lamps reached the row's end";
  EXPECT_LT(world.max_x, world.rail_length - 0.01) << "the drive wheels stay on the pipes";
  EXPECT_FALSE(world.wheel_past_edge);
  EXPECT_TRUE(logSays(world, "at the row's end"));
  if (HasFailure())
    for (const auto& l : world.lines) std::cout << l << "\n";
}

// A far wall 0.4 m past the rails' end: the guard stops the robot with the lidar 0.6 m from the wall, short of the
// row's end; the set is not reported treated, and the mission goes on.
TEST(UvMissionRowEnd, TheWallGuardStopsEarlierAndTheSetIsNotTreated) {
  const std::vector<RailSetTruth> sets = {{0.0}};
  SimulatedGreenhouse world(sets, 4);
  world.rail_length = 5.0;
  world.wall_past_end = 0.4;
  grn::UvMissionParams p;
  auto targets = targetsFor(sets, -1.2);
  targets[0].rail_length_m = world.rail_length;
  grn::UvMission mission(world, p, targets);
  EXPECT_EQ(mission.run(), "done");
  ASSERT_EQ(mission.reports().size(), 1u);
  const grn::RailSetReport& r = mission.reports()[0];
  EXPECT_FALSE(r.treated);
  EXPECT_NE(r.result.find("not every metre was lit"), std::string::npos) << r.result;
  // Stopped with base_link 0.6 + 0.45 m before the wall: the lamps' front edge at 4.40 m of 5 m.
  EXPECT_NEAR(r.lit_pct, 100.0 * (5.4 - 0.45 - 0.6 + 0.05) / 5.0, 1.5);
  // Stopped with the lidar (0.45 m ahead of the axle) about wall_guard_range from the wall: never near touching it.
  const double wall_x = world.rail_length + world.wall_past_end;
  EXPECT_NEAR(wall_x - (world.last_lights_off_x + 0.45), p.rail_run.wall_guard_range_m, 0.05);
  EXPECT_LT(world.max_x + 0.52, wall_x - 0.4);
  EXPECT_TRUE(logSays(world, "the far wall's guard stopped the robot"));
  EXPECT_FALSE(world.lights_on);
  if (HasFailure())
    for (const auto& l : world.lines) std::cout << l << "\n";
}

// The sim world's far wall, 1 m past the rails' end: row end or guard, the set is treated and the wheels stay on the
// pipes.
TEST(UvMissionRowEnd, WithTheWallAMetrePastTheRailsTheSetIsTreated) {
  const std::vector<RailSetTruth> sets = {{0.0}};
  for (unsigned seed : {4u, 5u, 6u}) {
    SimulatedGreenhouse world(sets, seed);
    world.rail_length = 5.0;
    grn::UvMissionParams p;
    auto targets = targetsFor(sets, -1.2);
    targets[0].rail_length_m = world.rail_length;
    grn::UvMission mission(world, p, targets);
    EXPECT_EQ(mission.run(), "done");
    ASSERT_EQ(mission.reports().size(), 1u);
    EXPECT_TRUE(mission.reports()[0].treated) << "seed " << seed << ": " << mission.reports()[0].result;
    EXPECT_LT(world.max_x, world.rail_length - 0.03) << "seed " << seed;
  }
}
