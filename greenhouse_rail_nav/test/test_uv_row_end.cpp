// The UV mission's run to a row's end of known length (rail_run.h): where the robot stops, the speed to get there
// with the far wall as a guard, and the share of the row the lamps lit.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "greenhouse_rail_nav/rail_run.h"

namespace grn = greenhouse_rail_nav;

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
