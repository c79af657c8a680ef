#include <cmath>
#include <cstdio>
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

// A ventilation line along the rows seen from the headland: a strip 0.14 m wide (the 0.16 m tube cut by the lidar's
// plane) starting 2.5 m ahead and 0.73-0.87 m to the left of the robot, which drives the greenhouse robot's mapping
// pattern (turn right, back 1 m, turn round, 0.8 m forth and back, turn back), UTM-30LX-like beams (0.25 deg, 1 cm
// noise, no return beyond 87.7 degrees of incidence as the simulator's datasheet lidar) into 2.5 cm cells. Its faces
// are met at 3-15 degrees: every beam runs through the cells of the face further along before it ends, and from near
// the line's axis beams glance off it without a return. Each face must be drawn over its first 3 m (where
// greenhouse_rail_nav's map analysis measures a row's faces), and the floor 10 cm in front of it be free.
struct Strip {
  double drawn = 0.0, drawn_3m = 0.0, floor_free = 0.0;  // per face (near, far) the lower of the two
};

Strip mapStrip(double grazing_keep_max_m, bool no_return_keeps_ends) {
  const double x0 = 2.5, x1 = 7.5, y_near = 0.731, y_far = 0.869;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> walls = {
      {{-3.5, -0.8}, {8.6, -0.8}}, {{-3.5, 2.4}, {8.6, 2.4}},    {{-3.5, -0.8}, {-3.5, 2.4}},
      {{8.6, -0.8}, {8.6, 2.4}},   {{x0, y_near}, {x1, y_near}}, {{x0, y_far}, {x1, y_far}},
      {{x0, y_near}, {x0, y_far}}, {{x1, y_near}, {x1, y_far}}};
  // Range to the nearest wall, 30 when nothing is met or the incidence is beyond the lidar's limit (no return).
  auto cast = [&](const Eigen::Vector2d& o, const Eigen::Vector2d& d) {
    double best = 30.0, sin_incidence_complement = 1.0;
    for (const auto& w : walls) {
      const Eigen::Vector2d e = w.second - w.first, f = w.first - o;
      const double den = d.x() * e.y() - d.y() * e.x();
      if (std::abs(den) < 1e-12) continue;
      const double t = (f.x() * e.y() - f.y() * e.x()) / den, u = (f.x() * d.y() - f.y() * d.x()) / den;
      if (t > 0.0 && u >= 0.0 && u <= 1.0 && t < best) {
        best = t;
        sin_incidence_complement = std::abs(den) / e.norm();  // cos(incidence) = |sin(angle between beam and wall)|
      }
    }
    return sin_incidence_complement < std::cos(1.53) ? 30.0 : best;
  };
  tn::MapperParams p;
  p.resolution_m = 0.025;
  p.grazing_keep_max_m = grazing_keep_max_m;
  p.no_return_keeps_ends = no_return_keeps_ends;
  tn::OccupancyMapper mapper(p);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  thorvald_base::Pose2D pose{};
  auto scanAt = [&]() {
    std::vector<Eigen::Vector2d> pts, no_return;
    const Eigen::Vector2d o = pose.transformPoint(kSensor);
    for (int i = 0; i < 1081; ++i) {
      const double a = -2.356 + 4.712 * i / 1080.0;
      const Eigen::Vector2d d(std::cos(pose.yaw + a), std::sin(pose.yaw + a));
      const double r = cast(o, d);
      const double rn = r >= 30.0 ? 30.0 : r + noise(rng);
      (r >= 30.0 ? no_return : pts).emplace_back(kSensor.x() + rn * std::cos(a), kSensor.y() + rn * std::sin(a));
    }
    mapper.addScan(pose, kSensor, pts, no_return);
  };
  const double dt = 0.05;
  const double segments[][3] = {{0.0, -0.4, 3.93}, {-0.2, 0.0, 5.0}, {0.0, 0.4, 7.85},
                                {0.2, 0.0, 4.0},   {-0.2, 0.0, 4.0}, {0.0, -0.4, 3.93}};
  for (const auto& s : segments)
    for (double t = 0.0; t < s[2]; t += dt) {
      pose = pose * thorvald_base::Pose2D{s[0] * dt, 0.0, s[1] * dt};
      scanAt();
    }
  const thorvald_map::OccupancyGrid g = mapper.occupancyGrid();
  // The map frame is the first pose's, which is the scene's frame (odometry exact; matching may move it by a few
  // millimetres).
  Strip out{1.0, 1.0, 1.0};
  for (const double face : {y_near, y_far}) {
    const double side = face == y_near ? -1.0 : 1.0;  // where the floor in front of this face lies
    int columns = 0, drawn = 0, free = 0, columns_3m = 0, drawn_3m = 0;
    for (double x = x0 + 0.1; x <= x1 - 0.1; x += p.resolution_m) {
      ++columns;
      const Eigen::Vector2i c = g.cellOf({x, face});
      bool hit = false;
      for (int dy = -1; dy <= 1; ++dy) hit = hit || (g.inside(c.x(), c.y() + dy) && g.at(c.x(), c.y() + dy) >= 65);
      drawn += hit;
      if (x < x0 + 3.0) ++columns_3m, drawn_3m += hit;
      const Eigen::Vector2i f = g.cellOf({x, face + side * 0.1});
      free += g.inside(f.x(), f.y()) && g.at(f.x(), f.y()) >= 0 && g.at(f.x(), f.y()) < 20;
    }
    out.drawn = std::min(out.drawn, static_cast<double>(drawn) / columns);
    out.drawn_3m = std::min(out.drawn_3m, static_cast<double>(drawn_3m) / columns_3m);
    out.floor_free = std::min(out.floor_free, static_cast<double>(free) / columns);
  }
  return out;
}

TEST(OccupancyMapper, ALineSeenAlongItsLengthStaysDrawn) {
  const tn::MapperParams defaults;
  const Strip both = mapStrip(defaults.grazing_keep_max_m, true);
  const Strip keep_only = mapStrip(defaults.grazing_keep_max_m, false);
  const Strip ends_only = mapStrip(0.0, true);
  const Strip neither = mapStrip(0.0, false);
  std::printf(
      "[          ] strip faces drawn over their first 3 m / all 5 m (the lower face): %.2f / %.2f by default, "
      "%.2f / %.2f without keeping ends from beams without a return, %.2f / %.2f without the grazing keep, "
      "%.2f / %.2f with neither; floor free %.2f\n",
      both.drawn_3m, both.drawn, keep_only.drawn_3m, keep_only.drawn, ends_only.drawn_3m, ends_only.drawn,
      neither.drawn_3m, neither.drawn, both.floor_free);
  EXPECT_GT(both.drawn_3m, 0.8);  // the analysis needs far less (a face seen at a twentieth of its stations)
  EXPECT_GT(both.floor_free, 0.9);
  EXPECT_GT(both.drawn, neither.drawn + 0.3);  // what the two rules are for: the line otherwise all but vanishes
  tn::MapperParams bad;
  bad.grazing_keep_max_m = -1.0;
  EXPECT_FALSE(bad.validate().empty());
}

}  // namespace
