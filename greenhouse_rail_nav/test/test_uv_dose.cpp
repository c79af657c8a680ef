// The UV dose along a rail set from known motion: the expected dose is lamp power / speed wherever the lit stretch
// passed at a constant speed.
#include <cmath>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "greenhouse_rail_nav/uv_dose.h"

namespace grn = greenhouse_rail_nav;

namespace {

grn::UvDoseParams lamps() {
  grn::UvDoseParams p;
  p.lamp_power_w = 60.0;
  p.lamp_length_m = 0.75;
  p.lamp_offset_m = -0.325;
  p.target_dose_j_per_m = 100.0;
  p.bin_m = 0.05;
  return p;
}

/// Drives base_link from `from` to `to` at `speed` [m/s] in 20 ms steps with the lamps `on`.
void drive(grn::RowDose* row, double from, double to, double speed, bool on) {
  const double dt = 0.02, dir = to > from ? 1.0 : -1.0;
  for (double s = from; dir * (to - s) > 1e-9;) {
    const double next = dir > 0 ? std::min(to, s + speed * dt) : std::max(to, s - speed * dt);
    row->add(s, next, std::abs(next - s) / speed, on);
    s = next;
  }
}

}  // namespace

TEST(UvDose, ParamsAreChecked) {
  EXPECT_EQ(lamps().validate(), "");
  grn::UvDoseParams p = lamps();
  p.lamp_power_w = 0.0;
  EXPECT_NE(p.validate().find("lamp_power"), std::string::npos);
  p = lamps();
  p.bin_m = 1.0;
  EXPECT_NE(p.validate().find("bin"), std::string::npos);
}

// 0.5 m/s with 60 W: 120 J per metre of row, everywhere the lit stretch passed over whole.
TEST(UvDose, ConstantSpeedGivesPowerOverSpeed) {
  grn::RowDose row(lamps(), 10.0);
  // The lit stretch reaches from base_link - 0.7 to base_link + 0.05: drive until it has passed the whole row.
  drive(&row, -0.2, 10.8, 0.5, true);
  for (std::size_t i = 0; i < row.dose().size(); ++i) EXPECT_NEAR(row.dose()[i], 120.0, 0.5) << "bin " << i;
  EXPECT_DOUBLE_EQ(row.coverage(), 1.0);
  EXPECT_TRUE(row.uncovered().empty());
  EXPECT_NEAR(row.meanDose(), 120.0, 0.5);
  // Twice the speed, half the dose: below the 100 J/m target, nothing covered.
  grn::RowDose fast(lamps(), 10.0);
  drive(&fast, -0.2, 10.8, 1.0, true);
  EXPECT_NEAR(fast.minDose(), 60.0, 0.5);
  EXPECT_DOUBLE_EQ(fast.coverage(), 0.0);
}

// Standing 30 s under the lamps with the lamps off adds nothing; with them on it adds power x time over the lit
// stretch.
TEST(UvDose, AStopWithTheLampsOffAddsNothing) {
  grn::RowDose row(lamps(), 10.0);
  drive(&row, -0.2, 5.0, 0.5, true);
  const std::vector<double> before = row.dose();
  row.add(5.0, 5.0, 30.0, false);
  EXPECT_EQ(row.dose(), before);
  row.add(5.0, 5.0, 30.0, true);
  // Bin [4.6, 4.65) lies wholly under the stretch centred at 4.675: + 60 W x 30 s / 0.75 m.
  EXPECT_NEAR(row.dose()[92] - before[92], 2400.0, 1e-6);
  EXPECT_EQ(row.dose()[60], before[60]);  // 3.0 m: not under the stretch
}

// Lamps off while base_link goes from 4 to 6 m. The stretch lit around base_link is [s - 0.7, s + 0.05]: a point p of
// the row gets 120 J/m x (the part of s in [p - 0.05, p + 0.7] driven with the lamps on) / 0.75 m, at least the 100 J/m
// target where that part is at least 0.625 m: up to p = 4.05 - 0.625 = 3.425 m and from p = 6.625 - 0.7 = 5.925 m.
// Between 4.05 and 5.3 m the row got nothing at all.
TEST(UvDose, AGapShowsAsUncovered) {
  grn::RowDose row(lamps(), 10.0);
  drive(&row, -0.2, 4.0, 0.5, true);
  drive(&row, 4.0, 6.0, 0.5, false);
  drive(&row, 6.0, 10.8, 0.5, true);
  EXPECT_NEAR(row.dose()[static_cast<std::size_t>(5.0 / 0.05)], 0.0, 1e-9);  // 4.975 .. 5.025 m: dark
  const auto gaps = row.uncovered();
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_NEAR(gaps[0].first, 3.425, 0.051);  // one bin
  EXPECT_NEAR(gaps[0].second, 5.925, 0.051);
  EXPECT_NEAR(row.coverage(), 1.0 - (gaps[0].second - gaps[0].first) / 10.0, 1e-9);
  EXPECT_NEAR(row.coverage(), 0.75, 0.011);
}

// The recorder splits a mission into sets by where the robot came onto the rails: a second entry at the first set's
// start is that set again (a resumed treatment fills its gap); one 1.6 m over is a new set.
TEST(UvDose, RecorderSplitsSetsByEntryAndAddsResumedPasses) {
  grn::UvDoseRecorder rec(lamps(), 4.0);
  double t = 0.0;
  auto pass = [&](double y0, double from, double to, double speed, bool on) {
    const double dt = 0.02, dir = to > from ? 1.0 : -1.0;
    for (double s = from; dir * (to - s) > -1e-9; s += dir * speed * dt, t += dt) rec.update(t, s, y0, 0.0, true, on);
  };
  rec.update(t, -1.0, 0.0, 0.0, false, false);
  pass(0.0, 0.0, 2.0, 0.5, true);  // set 0, lit as far as base_link 2 m
  EXPECT_EQ(rec.currentSet(), 0);
  pass(0.0, 2.0, 0.0, 0.5, false);  // backs out dark
  rec.update(t += 1.0, -1.0, 0.0, 0.0, false, false);
  EXPECT_EQ(rec.currentSet(), -1);
  pass(1.6, 0.0, 4.8, 0.5, true);  // set 1, whole
  rec.update(t += 1.0, -1.0, 1.6, 0.0, false, false);
  pass(0.0, 0.0, 1.5, 1.0, false);  // set 0 again: to where it stopped, dark
  pass(0.0, 1.5, 4.8, 0.5, true);   // and on from there, lit
  ASSERT_EQ(rec.sets(), 2u);
  EXPECT_NEAR(rec.dose(1).coverage(), 1.0, 1e-9);
  EXPECT_NEAR(rec.dose(0).coverage(), 1.0, 1e-9);
  // 120 J/m but in the first bin, which the stretch's 5 cm ahead of base_link reached only from the rails' start.
  EXPECT_NEAR(rec.dose(1).dose()[10], 120.0, 0.5);
  EXPECT_GT(rec.dose(1).minDose(), 100.0);
  // The report names both sets with their coverage.
  const grn::RowDose d0 = rec.dose(0), d1 = rec.dose(1);
  const YAML::Node y = YAML::Load(grn::doseReportYaml({{0, "/tmp/set0.png", &d0}, {1, "", &d1}}));
  ASSERT_EQ(y["uv_dose"].size(), 2u);
  EXPECT_NEAR(y["uv_dose"][1]["coverage_pct"].as<double>(), 100.0, 1e-9);
  EXPECT_EQ(y["uv_dose"][0]["png"].as<std::string>(), "/tmp/set0.png");
  const cv::Mat strip = grn::doseStrip(d0, 800, 40);
  EXPECT_GE(strip.cols, 800);
  EXPECT_EQ(strip.rows, 40);
}
