#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "thorvald_navigation/scan_matcher.h"
#include "thorvald_navigation/testing/synthetic_headland.h"

namespace tn = thorvald_navigation;
using tn::testing::HeadlandOptions;
using tn::testing::SyntheticHeadland;

namespace {

const Eigen::Vector2d kSensor(0.45, 0.0);

thorvald_base::Pose2D randomFloorPose(const SyntheticHeadland& world, std::mt19937* rng) {
  const auto& o = world.options();
  std::uniform_real_distribution<double> x(1.5, o.length_m - 1.5), y(1.0, o.depth_m - 1.0),
      yaw(-thorvald_base::kPi, thorvald_base::kPi);
  for (;;) {  // a pose with clearance from the clutter
    const thorvald_base::Pose2D p{x(*rng), y(*rng), yaw(*rng)};
    bool clear = true;
    for (int k = 0; k < 16 && clear; ++k) clear = world.castRay({p.x, p.y}, k * thorvald_base::kPi / 8, 0.7) >= 0.7;
    if (clear) return p;
  }
}

// Varied headlands: sizes, spacing, clutter and noise change with the seed.
HeadlandOptions variedHeadland(std::uint32_t seed) {
  HeadlandOptions o;
  o.seed = seed;
  o.length_m = 12.0 + 3.0 * (seed % 4);
  o.depth_m = 4.0 + 0.5 * (seed % 3);
  o.row_spacing_m = 1.4 + 0.1 * (seed % 5);
  o.clutter_boxes = 1 + static_cast<int>(seed % 4);
  return o;
}

TEST(ScanMatcher, RecoversPoseFromOdometryErrorsOnVariedHeadlands) {
  for (double res : {0.05, 0.025}) {
    double worst_xy = 0.0, worst_yaw = 0.0, sum_xy = 0.0;
    int n = 0;
    for (std::uint32_t seed = 1; seed <= 12; ++seed) {
      const SyntheticHeadland world(variedHeadland(seed));
      const tn::DistanceField field(world.truthMap(res), 1.0);
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> off(-0.1, 0.1), offyaw(-0.05, 0.05);
      const double noise = 0.005 + 0.005 * (seed % 5);  // 5..25 mm range noise
      for (int trial = 0; trial < 5; ++trial) {
        const thorvald_base::Pose2D truth = randomFloorPose(world, &rng);
        const auto pts = tn::subsample(world.scan(truth, kSensor, 1081, -2.356, 2.356, 30.0, noise, &rng), 180);
        const thorvald_base::Pose2D guess{truth.x + off(rng), truth.y + off(rng), truth.yaw + offyaw(rng)};
        const tn::MatchResult m = tn::matchScan(field, pts, guess, tn::ScanMatcherParams{});
        const double exy = std::hypot(m.pose.x - truth.x, m.pose.y - truth.y);
        worst_xy = std::max(worst_xy, exy);
        worst_yaw = std::max(worst_yaw, std::abs(thorvald_base::normalizeAngle(m.pose.yaw - truth.yaw)));
        sum_xy += exy;
        ++n;
        EXPECT_GT(m.inlier_fraction, 0.8) << "seed " << seed;
      }
    }
    // Grid quantisation dominates: a wall is drawn up to half a cell from where it is.
    EXPECT_LT(worst_xy, res) << "resolution " << res;
    EXPECT_LT(worst_yaw, 0.015) << "resolution " << res;
    EXPECT_LT(sum_xy / n, 0.6 * res) << "resolution " << res;
  }
}

TEST(ScanMatcherPrior, PriorHoldsThePoseAlongAFeaturelessCorridor) {
  // Two long parallel walls: x along the corridor is unobservable; the prior must keep it.
  thorvald_map::OccupancyGrid g(400, 60, 0.05, 0.0, 0.0, 0);
  for (int x = 0; x < 400; ++x) g.at(x, 0) = g.at(x, 59) = 100;
  const tn::DistanceField field(g, 1.0);
  std::vector<Eigen::Vector2d> pts;
  for (double x = -5.0; x <= 5.0; x += 0.1) {
    pts.emplace_back(x, 1.475);  // walls at y = 0.025 and 2.975 (cell centres), robot at y = 1.5
    pts.emplace_back(x, -1.475);
  }
  tn::ScanMatcherParams p;
  p.prior_sigma_xy_m = 0.05;
  p.prior_sigma_yaw_rad = 0.05;
  const tn::MatchResult m = tn::matchScan(field, pts, {10.0, 1.45, 0.0}, p);
  EXPECT_NEAR(m.pose.x, 10.0, 0.01);
  EXPECT_NEAR(m.pose.y, 1.5, 0.02);
  EXPECT_GT(m.covariance(0, 0), 10.0 * m.covariance(1, 1));  // uncertain along the corridor
}

TEST(ScanMatcher, BadInputGivesNoMatch) {
  const SyntheticHeadland world(HeadlandOptions{});
  const tn::DistanceField field(world.truthMap(0.05), 1.0);
  const tn::MatchResult empty = tn::matchScan(field, {}, {2, 2, 0}, tn::ScanMatcherParams{});
  EXPECT_EQ(empty.inlier_fraction, 0.0);
  const tn::MatchResult nan = tn::matchScan(field, {{1, 0}}, {std::nan(""), 2, 0}, tn::ScanMatcherParams{});
  EXPECT_EQ(nan.inlier_fraction, 0.0);
  tn::ScanMatcherParams bad;
  bad.sigma_hit_m = 0.0;
  EXPECT_NE(bad.validate(), "");
  tn::GlobalSearchParams gbad;
  gbad.step_yaw_rad = -1.0;
  EXPECT_NE(gbad.validate(), "");
}

TEST(GlobalSearch, FindsAKidnappedRobotAnywhereOnTheFloor) {
  int found = 0, trials = 0;
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    const SyntheticHeadland world(variedHeadland(seed + 20));
    const thorvald_map::OccupancyGrid map = world.truthMap(0.05);
    const tn::DistanceField field(map, 1.0);
    std::mt19937 rng(seed);
    for (int trial = 0; trial < 3; ++trial) {
      const thorvald_base::Pose2D truth = randomFloorPose(world, &rng);
      const auto pts = world.scan(truth, kSensor, 1081, -2.356, 2.356, 30.0, 0.01, &rng);
      const tn::GlobalResult g = tn::globalSearch(field, map, pts, tn::GlobalSearchParams{}, tn::ScanMatcherParams{});
      ++trials;
      ASSERT_TRUE(g.found);
      const bool ok = std::hypot(g.best.pose.x - truth.x, g.best.pose.y - truth.y) < 0.05 &&
                      std::abs(thorvald_base::normalizeAngle(g.best.pose.yaw - truth.yaw)) < 0.02;
      found += ok;
      // A wrong answer must not look certain: either it is right or it is flagged ambiguous or poorly matched.
      if (!ok) {
        EXPECT_TRUE(g.ambiguous || g.best.inlier_fraction < 0.8) << "seed " << seed << " trial " << trial;
      }
    }
  }
  EXPECT_GE(found, trials - 1);
}

TEST(GlobalSearch, WindowAroundARoughInitialPoseFindsTheTruePose) {
  int ok = 0, n = 0;
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const SyntheticHeadland world(variedHeadland(seed + 40));
    const thorvald_map::OccupancyGrid map = world.truthMap(0.05);
    const tn::DistanceField field(map, 1.0);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> off(-0.4, 0.4), offyaw(-0.25, 0.25);
    for (int trial = 0; trial < 3; ++trial) {
      const thorvald_base::Pose2D truth = randomFloorPose(world, &rng);
      const auto pts = world.scan(truth, kSensor, 1081, -2.356, 2.356, 30.0, 0.01, &rng);
      tn::GlobalSearchParams gp;
      gp.window_xy_m = 0.6;
      gp.window_yaw_rad = 0.35;
      gp.step_xy_m = 0.1;
      gp.step_yaw_rad = 0.05;
      gp.center = {truth.x + off(rng), truth.y + off(rng), truth.yaw + offyaw(rng)};
      const tn::GlobalResult g = tn::globalSearch(field, map, pts, gp, tn::ScanMatcherParams{});
      ++n;
      ok += g.found && std::hypot(g.best.pose.x - truth.x, g.best.pose.y - truth.y) < 0.05 &&
            std::abs(thorvald_base::normalizeAngle(g.best.pose.yaw - truth.yaw)) < 0.02;
    }
  }
  EXPECT_EQ(ok, n);
}

TEST(GlobalSearch, NothingToSearch) {
  const thorvald_map::OccupancyGrid walls_only(20, 20, 0.1, 0, 0, 100);
  const tn::DistanceField field(walls_only, 1.0);
  const std::vector<Eigen::Vector2d> pts{{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  EXPECT_FALSE(tn::globalSearch(field, walls_only, pts, {}, {}).found);
  EXPECT_FALSE(tn::globalSearch(field, walls_only, {}, {}, {}).found);
}

}  // namespace
