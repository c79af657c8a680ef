#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "thorvald_navigation/map_localizer.h"
#include "thorvald_navigation/testing/synthetic_headland.h"

namespace tn = thorvald_navigation;
using tn::testing::HeadlandOptions;
using tn::testing::SyntheticHeadland;

namespace {

const Eigen::Vector2d kSensor(0.45, 0.0);

struct Track {
  double rms_xy = 0.0, rms_yaw = 0.0, max_xy = 0.0;
  tn::LocalizationStatus final_status = tn::LocalizationStatus::kNoPose;
};

// Drives a slalom along the headland at 0.4 m/s with 40 Hz scans; odometry has scale and yaw-rate errors.
Track track(std::uint32_t seed, tn::MapLocalizer* loc, const SyntheticHeadland& world, bool start_known) {
  std::mt19937 rng(seed);
  thorvald_base::Pose2D truth{1.5, world.options().depth_m - 0.9, 0.0}, odom{};  // clear of the clutter band
  if (start_known) loc->setPose(truth, odom);
  const double dt = 0.025;
  double sum_xy = 0.0, sum_yaw = 0.0;
  int n = 0;
  Track t;
  const double duration = (world.options().length_m - 4.0) / 0.4;
  for (double time = 0.0; time < duration; time += dt) {
    const double v = 0.4, w = 0.1 * std::sin(0.5 * time);
    truth = truth * thorvald_base::Pose2D{v * dt, 0.0, w * dt};
    odom = odom * thorvald_base::Pose2D{v * 1.03 * dt, 0.0, (w * 1.02 + 0.01) * dt};
    const auto pts = world.scan(truth, kSensor, 1081, -2.356, 2.356, 30.0, 0.01, &rng);
    const tn::LocalizationUpdate u = loc->update(odom, pts);
    const double exy = std::hypot(u.pose.x - truth.x, u.pose.y - truth.y);
    const double eyaw = thorvald_base::normalizeAngle(u.pose.yaw - truth.yaw);
    if (time > 2.0) {  // after the first global fix has settled
      sum_xy += exy * exy;
      sum_yaw += eyaw * eyaw;
      t.max_xy = std::max(t.max_xy, exy);
      ++n;
    }
  }
  t.rms_xy = std::sqrt(sum_xy / n);
  t.rms_yaw = std::sqrt(sum_yaw / n);
  t.final_status = loc->status();
  return t;
}

TEST(MapLocalizer, TracksThroughOdometryDriftOnVariedHeadlands) {
  // The map's cell size bounds the accuracy (walls are drawn up to half a cell off): 5 cm and 2.5 cm maps.
  for (const double res : {0.05, 0.025}) {
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
      HeadlandOptions o;
      o.seed = seed;
      o.length_m = 12.0 + 2.0 * seed;
      o.row_spacing_m = 1.4 + 0.1 * seed;
      const SyntheticHeadland world(o);
      tn::MapLocalizer loc{tn::LocalizerParams{}};
      ASSERT_EQ(loc.setMap(world.truthMap(res)), "");
      const Track t = track(seed, &loc, world, true);
      EXPECT_LT(t.rms_xy, 0.8 * res) << "seed " << seed << " resolution " << res;
      EXPECT_LT(t.rms_yaw, 0.009) << "seed " << seed << " resolution " << res;
      EXPECT_LT(t.max_xy, 1.5 * res) << "seed " << seed << " resolution " << res;
      EXPECT_EQ(t.final_status, tn::LocalizationStatus::kLocalized);
    }
  }
}

TEST(MapLocalizer, KidnappedRobotRecoversByGlobalLocalization) {
  HeadlandOptions o;
  o.seed = 5;
  const SyntheticHeadland world(o);
  tn::MapLocalizer loc{tn::LocalizerParams{}};
  ASSERT_EQ(loc.setMap(world.truthMap(0.05)), "");
  // Told it is somewhere it is not: tracking fails and reports lost.
  std::mt19937 rng(1);
  const thorvald_base::Pose2D truth{9.0, 2.5, 2.0};
  loc.setPose({4.0, 1.5, 0.0}, {});
  const auto pts = world.scan(truth, kSensor, 1081, -2.356, 2.356, 30.0, 0.01, &rng);
  for (int i = 0; i < 20; ++i) loc.update({}, pts);
  EXPECT_EQ(loc.status(), tn::LocalizationStatus::kLost);
  loc.requestGlobalLocalization();
  const auto g = loc.update({}, pts);
  EXPECT_TRUE(g.used) << g.message;
  EXPECT_NEAR(g.pose.x, truth.x, 0.05);
  EXPECT_NEAR(g.pose.y, truth.y, 0.05);
  EXPECT_NEAR(thorvald_base::normalizeAngle(g.pose.yaw - truth.yaw), 0.0, 0.02);
  EXPECT_EQ(g.status, tn::LocalizationStatus::kUncertain);  // until confirmed by the next scans
  for (int i = 0; i < 10; ++i) loc.update({}, pts);
  EXPECT_EQ(loc.status(), tn::LocalizationStatus::kLocalized);
}

// An odometry jump (the drive starved of CPU: the wheel odometry leaps while the robot does not move): the match
// that fits the map lies farther than max_jump from the prediction. The localiser must say lost at once, not drive on
// the prediction, and find the robot again with its re-check around the odometry.
struct JumpRun {
  int scans_to_lost = -1, scans_to_relocalised = -1, scans_to_localized = -1;
  double final_error_m = 1e9;
  tn::LocalizationStatus final_status = tn::LocalizationStatus::kNoPose;
};

JumpRun odometryJump(std::uint32_t seed, double jump_m, double jump_dir_rad, const tn::LocalizerParams& params) {
  HeadlandOptions o;
  o.seed = seed;
  o.length_m = 12.0 + seed;
  const SyntheticHeadland world(o);
  tn::MapLocalizer loc{params};
  EXPECT_EQ(loc.setMap(world.truthMap(0.05)), "");
  std::mt19937 rng(seed);
  const thorvald_base::Pose2D truth{4.0 + 0.5 * seed, o.depth_m - 1.0, 0.2 * seed};
  thorvald_base::Pose2D odom{1.0, -2.0, 0.3};
  loc.setPose(truth, odom);
  for (int i = 0; i < 10; ++i) loc.update(odom, world.scan(truth, kSensor, 1081, -2.356, 2.356, 30.0, 0.01, &rng));
  EXPECT_EQ(loc.status(), tn::LocalizationStatus::kLocalized);
  odom = odom * thorvald_base::Pose2D{jump_m * std::cos(jump_dir_rad), jump_m * std::sin(jump_dir_rad), 0.0};
  JumpRun r;
  for (int i = 1; i <= 60; ++i) {
    const auto u = loc.update(odom, world.scan(truth, kSensor, 1081, -2.356, 2.356, 30.0, 0.01, &rng));
    if (r.scans_to_lost < 0 && u.status == tn::LocalizationStatus::kLost) {
      r.scans_to_lost = i;
      EXPECT_FALSE(u.used) << u.message;
    }
    if (r.scans_to_lost > 0 && r.scans_to_relocalised < 0 && u.used) r.scans_to_relocalised = i;
    if (r.scans_to_relocalised > 0 && r.scans_to_localized < 0 && u.status == tn::LocalizationStatus::kLocalized)
      r.scans_to_localized = i;
    r.final_error_m = std::hypot(u.pose.x - truth.x, u.pose.y - truth.y);
  }
  r.final_status = loc.status();
  return r;
}

TEST(MapLocalizer, OdometryJumpIsReportedLostAtOnceAndRecheckedBack) {
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    // 0.55 to 0.85 m in varied directions: beyond max_jump (0.5 m), within the re-check's 1 m.
    const JumpRun r = odometryJump(seed, 0.45 + 0.1 * seed, 1.3 * seed, tn::LocalizerParams{});
    // At once when the match fits the map well beyond max_jump; after lost_after_scans (10) weak matches when the
    // prior holds the match near the wrong prediction. Never a wrong pose taken for a good one meanwhile.
    EXPECT_GE(r.scans_to_lost, 1) << "seed " << seed;
    EXPECT_LE(r.scans_to_lost, 11) << "seed " << seed;
    EXPECT_EQ(r.scans_to_relocalised, r.scans_to_lost + 1) << "seed " << seed;   // the re-check on the next scan
    EXPECT_GT(r.scans_to_localized, r.scans_to_relocalised) << "seed " << seed;  // confirmed by later scans
    EXPECT_EQ(r.final_status, tn::LocalizationStatus::kLocalized) << "seed " << seed;
    EXPECT_LT(r.final_error_m, 0.05) << "seed " << seed;
  }
}

TEST(MapLocalizer, WithoutTheRecheckAJumpStaysLost) {
  tn::LocalizerParams p;
  p.recheck_xy_m = 0.0;
  const JumpRun r = odometryJump(2, 0.7, 0.5, p);
  EXPECT_GE(r.scans_to_lost, 1);
  EXPECT_LE(r.scans_to_lost, 11);
  EXPECT_EQ(r.final_status, tn::LocalizationStatus::kLost);
  EXPECT_NEAR(r.final_error_m, 0.7, 0.05);  // the prediction, never taken for the truth
}

TEST(MapLocalizer, NoPoseNoMapAndBadInput) {
  tn::MapLocalizer loc{tn::LocalizerParams{}};
  EXPECT_EQ(loc.update({}, {{1, 0}}).message, "no map");
  EXPECT_NE(loc.setMap(thorvald_map::OccupancyGrid(10, 10, 0.1, 0, 0, 0)), "");  // no walls
  EXPECT_NE(loc.setMap(thorvald_map::OccupancyGrid()), "");
  const SyntheticHeadland world(HeadlandOptions{});
  ASSERT_EQ(loc.setMap(world.truthMap(0.05)), "");
  std::mt19937 rng(2);
  const auto pts = world.scan({5, 2, 0}, kSensor, 541, -2.356, 2.356, 30.0, 0.01, &rng);
  EXPECT_FALSE(loc.update({}, pts).used);  // no initial pose yet
  EXPECT_EQ(loc.status(), tn::LocalizationStatus::kNoPose);
  loc.setPose({5, 2, 0}, {});
  EXPECT_FALSE(loc.update({std::nan(""), 0, 0}, pts).used);
  EXPECT_FALSE(loc.update({}, {{1, 0}}).used);
  EXPECT_TRUE(loc.update({}, pts).used);
  tn::LocalizerParams bad;
  bad.lost_inlier_fraction = 0.9;
  EXPECT_NE(bad.validate(), "");
  tn::LocalizerParams bad_recheck;
  bad_recheck.recheck_xy_m = -1.0;
  EXPECT_NE(bad_recheck.validate(), "");
  bad_recheck.recheck_xy_m = 1.0;
  bad_recheck.recheck_every_scans = 0;
  EXPECT_NE(bad_recheck.validate(), "");
}

}  // namespace
