#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "thorvald_navigation/distance_field.h"
#include "thorvald_navigation/occupancy_mapper.h"
#include "thorvald_navigation/testing/synthetic_headland.h"

namespace tn = thorvald_navigation;
using tn::testing::HeadlandOptions;
using tn::testing::SyntheticHeadland;

namespace {

const Eigen::Vector2d kSensor(0.45, 0.0);

struct Drive {
  double final_err_m = 0.0;
  double wall_err_m = 0.0;  // mean distance of mapped wall cells to the true walls
  double covered = 0.0;     // fraction of true floor cells mapped free
  int scans = 0;
};

// Drives back and forth along the headland; odometry has a yaw-rate bias and scale error (drift of metres over
// the run), the map is compared to the truth in the first pose's frame.
Drive mapHeadland(std::uint32_t seed, bool drift) {
  HeadlandOptions o;
  o.seed = seed;
  o.length_m = 14.0 + 2.0 * (seed % 3);
  const SyntheticHeadland world(o);
  tn::MapperParams p;
  tn::OccupancyMapper mapper(p);
  std::mt19937 rng(seed);
  const thorvald_base::Pose2D start{1.5, o.depth_m - 0.7, 0.0};  // above the clutter band, below the rows
  thorvald_base::Pose2D truth = start, odom{};
  const double dt = 0.05;
  Drive result;
  const double straight_s = (o.length_m - 3.0) / 0.5, turn_s = thorvald_base::kPi / 0.5;
  const double legs[][3] = {{0.5, 0.0, straight_s}, {0.0, 0.5, turn_s}, {0.5, 0.0, straight_s}, {0.0, -0.5, turn_s}};
  for (const auto& leg : legs) {
    for (double t = 0.0; t < leg[2] - 1e-9; t += dt) {
      const double v = leg[0], w = leg[1];
      truth = truth * thorvald_base::Pose2D{v * dt, 0.0, w * dt};
      const double v_odom = drift ? v * 1.02 : v, w_odom = drift ? w * 1.01 + 0.01 : w;
      odom = odom * thorvald_base::Pose2D{v_odom * dt, 0.0, w_odom * dt};
      const auto pts = world.scan(truth, kSensor, 541, -2.356, 2.356, 30.0, 0.01, &rng);
      mapper.addScan(odom, kSensor, pts, {});
    }
  }
  // Truth of the final pose in the map frame (map frame = start pose).
  const thorvald_base::Pose2D truth_in_map = start.inverse() * truth;
  const thorvald_base::Pose2D est = mapper.mapToOdom() * odom;
  result.final_err_m = std::hypot(est.x - truth_in_map.x, est.y - truth_in_map.y);
  const thorvald_map::OccupancyGrid map = mapper.occupancyGrid();
  const thorvald_map::OccupancyGrid truth_map = world.truthMap(0.05);
  const tn::DistanceField truth_field(truth_map, 2.0);
  double sum = 0.0;
  int walls = 0, free_ok = 0, floor = 0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x)
      if (map.at(x, y) >= 65) {
        sum += truth_field.distance(start.transformPoint(map.cellCentre(x, y)));
        ++walls;
      }
  for (int y = 0; y < truth_map.height; ++y)
    for (int x = 0; x < truth_map.width; ++x) {
      const Eigen::Vector2d c = truth_map.cellCentre(x, y);
      if (truth_map.at(x, y) != 0 || c.y() > o.depth_m) continue;
      ++floor;
      const Eigen::Vector2i m = map.cellOf(start.inverse().transformPoint(c));
      free_ok += map.inside(m.x(), m.y()) && map.at(m.x(), m.y()) >= 0 && map.at(m.x(), m.y()) < 20;
    }
  result.wall_err_m = walls > 0 ? sum / walls : 1e9;
  result.covered = static_cast<double>(free_ok) / floor;
  result.scans = mapper.scansUsed();
  return result;
}

TEST(OccupancyMapper, ScanMatchingRemovesOdometryDrift) {
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    const Drive d = mapHeadland(seed, true);
    EXPECT_LT(d.final_err_m, 0.10) << "seed " << seed;
    EXPECT_LT(d.wall_err_m, 0.05) << "seed " << seed;
    EXPECT_GT(d.covered, 0.9) << "seed " << seed;
    EXPECT_GT(d.scans, 50);
  }
}

// A wall seen at every angle from a robot driving along it, its face at several places inside a cell: the wall's
// first occupied cell must hold the face on average (grazing beams cross that cell's free part before they end and
// must not clear it; scan matching must not slide the robot into a wall drawn two cells thick and so push the wall
// outwards scan after scan). Independent expectation: the first occupied cell's centre lies (0.5 - f) cells behind a
// face at fraction f of its cell.
TEST(OccupancyMapper, WallDrawnInTheCellHoldingItsFace) {
  for (const double res : {0.025, 0.05}) {
    double sum_dev = 0.0;
    const double fracs[] = {0.1, 0.35, 0.6, 0.9};
    for (const double frac : fracs) {
      const double wall_y = 1.5 + frac * res, end_x = 8.0;  // side wall and an end wall that holds the matcher
      tn::MapperParams p;
      p.resolution_m = res;
      tn::OccupancyMapper mapper(p);
      std::mt19937 rng(static_cast<std::uint32_t>(1000 * frac + 1000000 * res));
      std::normal_distribution<double> noise(0.0, 0.005);
      for (double x = 0.0; x <= 4.5; x += 0.05) {
        const Eigen::Vector2d sensor(x + kSensor.x(), kSensor.y());
        std::vector<Eigen::Vector2d> pts;
        for (int i = 0; i < 541; ++i) {
          const double a = -2.356 + 4.712 * i / 540.0;
          const double c = std::cos(a), s = std::sin(a);
          double r = 30.0;
          if (s > 1e-6) r = std::min(r, (wall_y - sensor.y()) / s);
          if (c > 1e-6) r = std::min(r, (end_x - sensor.x()) / c);
          if (r >= 30.0) continue;
          r += noise(rng);
          pts.emplace_back(kSensor.x() + r * c, kSensor.y() + r * s);
        }
        mapper.addScan({x, 0.0, 0.0}, kSensor, pts, {});
      }
      const thorvald_map::OccupancyGrid g = mapper.occupancyGrid();
      // The face where the mapper's own frame puts it: the drawing rule is tested against the frame the scans were
      // placed in. The second scan's match turns that frame by about 3 mrad in this scene (README, Limits), which
      // tilts the face by up to a cell over the 4 m; against the odometry frame that tilt would be counted here.
      const thorvald_base::Pose2D m2o = mapper.mapToOdom();
      int columns = 0;
      double dev = 0.0;
      for (double x = 0.5; x <= 4.5; x += res) {
        const Eigen::Vector2i c0 = g.cellOf({x, 0.5});
        const double x_odom = x - m2o.x;  // the wall's point below this column, to first order in the small yaw
        const double face_y = m2o.transformPoint({x_odom, wall_y}).y();
        const double face_cell_y = g.cellCentre(c0.x(), g.cellOf({x, face_y}).y()).y();
        for (int cy = c0.y(); cy < g.height; ++cy) {
          if (g.at(c0.x(), cy) < 65) continue;
          ++columns;
          dev += g.cellCentre(c0.x(), cy).y() - face_cell_y;
          break;
        }
      }
      ASSERT_GT(columns, static_cast<int>(3.5 / res)) << "resolution " << res << " face at " << frac;
      dev /= columns;
      EXPECT_LT(std::abs(dev), 0.5 * res) << "resolution " << res << " face at " << frac << " of a cell";
      sum_dev += dev;
    }
    EXPECT_LT(std::abs(sum_dev / 4.0), 0.3 * res) << "resolution " << res << ": walls drawn off their face on average";
  }
}

TEST(OccupancyMapper, SkipsScansWhileStandingAndRejectsBadInput) {
  tn::OccupancyMapper mapper{tn::MapperParams{}};
  const SyntheticHeadland world(HeadlandOptions{});
  std::mt19937 rng(3);
  const auto pts = world.scan({3, 2, 0}, kSensor, 541, -2.356, 2.356, 30.0, 0.0, &rng);
  EXPECT_TRUE(mapper.addScan({}, kSensor, pts, {}).integrated);
  EXPECT_FALSE(mapper.addScan({0.01, 0, 0}, kSensor, pts, {}).integrated);
  EXPECT_EQ(mapper.scansUsed(), 1);
  const auto nan = mapper.addScan({std::nan(""), 0, 0}, kSensor, pts, {});
  EXPECT_FALSE(nan.integrated);
  EXPECT_NE(nan.rejected, "");
  EXPECT_NE(mapper.addScan({1, 0, 0}, kSensor, {{1, 0}}, {}).rejected, "");
  EXPECT_GT(mapper.knownAreaM2(), 10.0);
  tn::MapperParams bad;
  bad.resolution_m = 0.0;
  EXPECT_NE(bad.validate(), "");
}

TEST(OccupancyMapper, GridGrowsBeyondItsFirstSize) {
  tn::MapperParams p;
  p.initial_size_m = 4.0;
  tn::OccupancyMapper mapper(p);
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < 20; ++i) pts.emplace_back(9.025, -0.975 + 0.1 * i);  // a wall 9 m ahead (cell centres)
  mapper.addScan({}, {0, 0}, pts, {});
  const thorvald_map::OccupancyGrid g = mapper.occupancyGrid();
  const Eigen::Vector2i c = g.cellOf({9.025, 0.025});
  ASSERT_TRUE(g.inside(c.x(), c.y()));
  EXPECT_GE(g.at(c.x(), c.y()), 65);
  const Eigen::Vector2i f = g.cellOf({4.0, 0.0});
  EXPECT_LT(g.at(f.x(), f.y()), 50);  // one pass of a beam: more likely free than not
  EXPECT_GE(g.at(f.x(), f.y()), 0);
}

// The odometry prior's weight: driving 4 m along the headland with odometry 5 % long, the default prior leaves the
// walls to correct the pose, and a prior far tighter than the scan's precision keeps the odometry's error whole.
double straightDriveError(double odom_sigma_xy_m, double odom_sigma_fraction) {
  HeadlandOptions o;
  o.clutter_boxes = 0;
  const SyntheticHeadland world(o);
  tn::MapperParams p;
  p.odom_sigma_xy_m = odom_sigma_xy_m;
  p.odom_sigma_fraction = odom_sigma_fraction;
  tn::OccupancyMapper mapper(p);
  std::mt19937 rng(11);
  const thorvald_base::Pose2D start{2.0, o.depth_m - 0.7, 0.0};
  thorvald_base::Pose2D truth = start, odom{};
  const double dt = 0.05, v = 0.5;
  for (int i = 0; i < 160; ++i) {
    truth = truth * thorvald_base::Pose2D{v * dt, 0.0, 0.0};
    odom = odom * thorvald_base::Pose2D{1.05 * v * dt, 0.0, 0.0};
    mapper.addScan(odom, kSensor, world.scan(truth, kSensor, 541, -2.356, 2.356, 30.0, 0.01, &rng), {});
  }
  const thorvald_base::Pose2D est = mapper.mapToOdom() * odom, truth_in_map = start.inverse() * truth;
  return std::hypot(est.x - truth_in_map.x, est.y - truth_in_map.y);
}

TEST(OccupancyMapper, OdometryPriorWeighsAgainstTheScan) {
  EXPECT_LT(straightDriveError(0.01, 0.1), 0.03);  // the default: the walls correct 20 cm of odometry error
  EXPECT_GT(straightDriveError(1e-4, 0.0), 0.15);  // 0.1 mm: the pose is the odometry's
  tn::MapperParams bad;
  bad.odom_sigma_fraction = -0.1;
  EXPECT_FALSE(bad.validate().empty());
}

}  // namespace
