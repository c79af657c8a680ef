#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "thorvald_navigation/costmap.h"
#include "thorvald_navigation/grid_planner.h"
#include "thorvald_navigation/testing/synthetic_headland.h"

namespace tn = thorvald_navigation;

namespace {

// A 10 m x 4 m room with a wall from the bottom up to y = 2.5 in the middle (x = 5 m).
thorvald_map::OccupancyGrid roomWithBaffle() {
  thorvald_map::OccupancyGrid g(200, 80, 0.05, 0.0, 0.0, thorvald_map::kFree);
  for (int x = 0; x < 200; ++x) g.at(x, 0) = g.at(x, 79) = thorvald_map::kOccupied;
  for (int y = 0; y < 80; ++y) g.at(0, y) = g.at(199, y) = thorvald_map::kOccupied;
  for (int y = 0; y < 50; ++y) g.at(100, y) = thorvald_map::kOccupied;
  return g;
}

// Every point of the path keeps at least `r` from every blocked cell.
double minClearance(const tn::Costmap& cm, const std::vector<Eigen::Vector2d>& path) {
  const auto& g = cm.geometry();
  double best = 1e9;
  for (std::size_t i = 1; i < path.size(); ++i)
    for (double s = 0.0; s <= 1.0; s += 0.01) {
      const Eigen::Vector2d p = path[i - 1] + s * (path[i] - path[i - 1]);
      for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x)
          if (cm.blocker(x, y) != tn::Blocker::kNone) best = std::min(best, (g.cellCentre(x, y) - p).norm());
    }
  return best;
}

TEST(GridPlanner, GoesAroundTheWallKeepingThePlanningRadius) {
  tn::CostmapParams cp;
  cp.planning_radius_m = 0.4;
  const tn::Costmap cm(roomWithBaffle(), thorvald_map::OccupancyGrid(), cp);
  const tn::PlanResult r = tn::planPath(cm, {2.0, 1.0}, {8.0, 1.0}, tn::PlannerParams{});
  ASSERT_TRUE(r.ok) << r.error;
  // Over the baffle's end (y = 2.5 m + radius): at least twice hypot(3, 1.85), not much more.
  EXPECT_GT(r.length_m, 2.0 * std::hypot(3.0, 1.85) - 0.05);
  EXPECT_LT(r.length_m, 2.0 * std::hypot(3.0, 1.85) + 1.0);
  EXPECT_GT(minClearance(cm, r.path), 0.4 - 0.05);
  EXPECT_NEAR(r.path.front().x(), 2.0, 1e-12);
  EXPECT_NEAR(r.path.back().x(), 8.0, 1e-12);
}

TEST(GridPlanner, RefusesGoalsInKeepOutWallsAndUnknownWithTheReason) {
  thorvald_map::OccupancyGrid map = roomWithBaffle();
  for (int y = 60; y < 79; ++y)
    for (int x = 150; x < 199; ++x) map.at(x, y) = thorvald_map::kUnknown;
  thorvald_map::OccupancyGrid keep_out(20, 8, 0.5, 0.0, 0.0,
                                       thorvald_map::kFree);  // coarser grid than the map: resampled
  for (int x = 0; x < 20; ++x) keep_out.at(x, 6) = keep_out.at(x, 7) = thorvald_map::kOccupied;  // y >= 3 m
  const tn::Costmap cm(map, keep_out, tn::CostmapParams{});
  const auto behind = tn::planPath(cm, {2.0, 1.0}, {3.0, 3.5}, tn::PlannerParams{});
  EXPECT_FALSE(behind.ok);
  EXPECT_NE(behind.error.find("keep-out"), std::string::npos) << behind.error;
  const auto wall = tn::planPath(cm, {2.0, 1.0}, {5.02, 1.0}, tn::PlannerParams{});
  EXPECT_NE(wall.error.find("wall"), std::string::npos) << wall.error;
  const auto near_wall = tn::planPath(cm, {2.0, 1.0}, {5.2, 1.0}, tn::PlannerParams{});
  EXPECT_NE(near_wall.error.find("planning radius"), std::string::npos) << near_wall.error;
  const auto outside = tn::planPath(cm, {2.0, 1.0}, {50.0, 1.0}, tn::PlannerParams{});
  EXPECT_NE(outside.error.find("outside"), std::string::npos);
  const auto nan = tn::planPath(cm, {2.0, std::nan("")}, {3.0, 1.0}, tn::PlannerParams{});
  EXPECT_FALSE(nan.ok);
  const auto blocked = tn::planPath(cm, {2.0, 1.0}, {8.0, 1.0}, tn::PlannerParams{});
  EXPECT_FALSE(blocked.ok);  // the gap above the baffle (2.5 .. 3 m) is narrower than twice the radius
  EXPECT_NE(blocked.error.find("no collision-free path"), std::string::npos);
}

TEST(GridPlanner, ObstaclesBlockAndReplanGoesAround) {
  thorvald_map::OccupancyGrid map(200, 80, 0.05, 0.0, 0.0, thorvald_map::kFree);
  tn::Costmap cm(map, thorvald_map::OccupancyGrid(), tn::CostmapParams{});
  const auto straight = tn::planPath(cm, {1.0, 2.0}, {9.0, 2.0}, tn::PlannerParams{});
  ASSERT_TRUE(straight.ok);
  EXPECT_NEAR(straight.length_m, 8.0, 0.05);
  std::vector<Eigen::Vector2d> person;
  for (double a = 0.0; a < 2 * thorvald_base::kPi; a += 0.1)
    person.emplace_back(5.0 + 0.25 * std::cos(a), 2.0 + 0.25 * std::sin(a));
  cm.setObstacles(person);
  const tn::Footprint fp = tn::rectangleFootprint(-0.5, 0.5, -0.3, 0.3);
  EXPECT_EQ(cm.footprintBlocker({4.6, 2.0, 0.0}, fp), tn::Blocker::kObstacle);
  EXPECT_EQ(cm.footprintBlocker({3.0, 2.0, 0.0}, fp), tn::Blocker::kNone);
  const auto around = tn::planPath(cm, {1.0, 2.0}, {9.0, 2.0}, tn::PlannerParams{});
  ASSERT_TRUE(around.ok) << around.error;
  EXPECT_GT(around.length_m, 8.05);
  EXPECT_GT(minClearance(cm, around.path), 0.35 - 0.05);
  cm.setObstacles({});  // the person left
  EXPECT_NEAR(tn::planPath(cm, {1.0, 2.0}, {9.0, 2.0}, tn::PlannerParams{}).length_m, 8.0, 0.05);
}

// A headland edge at x = 5 m (keep-out beyond it) with a mapped structure (a ventilation line's end, 0.16 m wide)
// starting 0.08 m past it at y = 2.8 m, and a mapped post (0.2 m square) at (3.65, 2.8), 6 cm beside the
// robot's padded box on its way from (4.2, 2) to (4.2, 3.6).
struct EdgeScene {
  thorvald_map::OccupancyGrid map{160, 120, 0.05, 0.0, 0.0, thorvald_map::kFree};
  thorvald_map::OccupancyGrid keep_out{160, 120, 0.05, 0.0, 0.0, thorvald_map::kFree};
  EdgeScene() {
    for (int y = 0; y < map.height; ++y)
      for (int x = 0; x < map.width; ++x) {
        const Eigen::Vector2d c = map.cellCentre(x, y);
        if (c.x() > 5.0) keep_out.at(x, y) = thorvald_map::kOccupied;
        if (c.x() > 5.08 && std::abs(c.y() - 2.8) < 0.08) map.at(x, y) = thorvald_map::kOccupied;
        if (std::abs(c.x() - 3.65) < 0.1 && std::abs(c.y() - 2.8) < 0.1) map.at(x, y) = thorvald_map::kOccupied;
      }
  }
};

// The greenhouse robot's box (base_link at its front axle) with 0.05 m padding.
tn::Footprint greenhouseFootprint() { return tn::rectangleFootprint(-0.91, 0.23, -0.39, 0.39); }

TEST(ObstacleCheck, LidarPointsOnMappedStructureBesideThePathDoNotStopTheRobot) {
  const EdgeScene scene;
  tn::Costmap cm(scene.map, scene.keep_out, tn::CostmapParams{});
  const tn::Footprint fp = greenhouseFootprint();
  // From one target 0.8 m before the edge to the next 1.6 m along it: turn left, drive, turn back.
  const thorvald_base::Pose2D start{4.2, 2.0, 0.0};
  const std::vector<Eigen::Vector2d> path{{4.2, 2.0}, {4.2, 3.6}};
  std::mt19937 rng(15);
  std::normal_distribution<double> noise(0.0, 0.02);  // range noise and the localiser's error
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Eigen::Vector2d> pts;
    // The lidar sees the vent line's end face and sides, the post's faces, and the floor beyond the edge.
    for (double y = 2.72; y <= 2.88; y += 0.01) pts.emplace_back(5.08 + noise(rng), y + noise(rng));
    for (double x = 5.08; x <= 6.5; x += 0.02) {
      pts.emplace_back(x + noise(rng), 2.72 + noise(rng));
      pts.emplace_back(x + noise(rng), 2.88 + noise(rng));
    }
    for (double y = 2.7; y <= 2.9; y += 0.01) pts.emplace_back(3.75 + noise(rng), y + noise(rng));
    for (double y = 0.5; y <= 5.5; y += 0.05) pts.emplace_back(5.3 + noise(rng), y);
    cm.setObstacles(pts);
    EXPECT_EQ(cm.obstaclePoints(), 0u) << "trial " << trial;
    EXPECT_EQ(cm.knownStructurePoints(), pts.size());
    EXPECT_LT(tn::sweptObstacleDistance(cm, fp, start, path, 1, 2.5, false), 0.0) << "trial " << trial;
  }
  // Without the tolerance, points of the post's face seen 7 cm off the map (inside the padded box) stop the robot.
  tn::CostmapParams strict;
  strict.known_structure_tolerance_m = 0.0;
  tn::Costmap raw(scene.map, scene.keep_out, strict);
  std::vector<Eigen::Vector2d> post;
  for (double y = 2.7; y <= 2.9; y += 0.01) post.emplace_back(3.82, y);
  raw.setObstacles(post);
  EXPECT_GT(raw.obstaclePoints(), 0u);
  EXPECT_GE(tn::sweptObstacleDistance(raw, fp, start, path, 1, 2.5, false), 0.0);
}

TEST(ObstacleCheck, UnmappedPointsInTheSweptFootprintStopTheRobot) {
  const EdgeScene scene;
  tn::Costmap cm(scene.map, scene.keep_out, tn::CostmapParams{});
  const tn::Footprint fp = greenhouseFootprint();
  const thorvald_base::Pose2D start{4.2, 2.0, 0.0};
  const std::vector<Eigen::Vector2d> path{{4.2, 2.0}, {4.2, 3.6}};
  // A small unmapped object (a crate, a foot) on the way: 1 m along the path.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector2d c(4.2 + jitter(rng), 3.0 + jitter(rng));
    std::vector<Eigen::Vector2d> pts;
    for (double a = 0.0; a < 2 * thorvald_base::kPi; a += 0.3)
      pts.push_back(c + 0.06 * Eigen::Vector2d(std::cos(a), std::sin(a)));
    cm.setObstacles(pts);
    EXPECT_EQ(cm.obstaclePoints(), pts.size());
    const double d = tn::sweptObstacleDistance(cm, fp, start, path, 1, 2.5, false);
    // Met when the box's front (0.23 m ahead of base_link after the turn) reaches it.
    EXPECT_GT(d, 0.5) << "trial " << trial;
    EXPECT_LT(d, 1.0) << "trial " << trial;
    // Not looked at when it lies beyond the distance checked ahead.
    EXPECT_LT(tn::sweptObstacleDistance(cm, fp, start, path, 1, 0.4, false), 0.0);
  }
  // Beside the path: a differential robot heads along it (0.39 m either side), an omnidirectional one keeps its
  // heading across it (its 0.91 m rear reaches the point).
  cm.setObstacles({{3.5, 3.0}});
  EXPECT_LT(tn::sweptObstacleDistance(cm, fp, start, path, 1, 2.5, false), 0.0);
  EXPECT_GE(tn::sweptObstacleDistance(cm, fp, start, path, 1, 2.5, true), 0.0);
  // Beside the path, outside the swept box and beyond the rear's reach in the turn: no stop.
  cm.setObstacles({{3.3, 2.6}, {4.75, 3.0}, {3.4, 1.2}});
  EXPECT_EQ(cm.obstaclePoints(), 3u);
  EXPECT_LT(tn::sweptObstacleDistance(cm, fp, start, path, 1, 2.5, false), 0.0);
  // Under the robot now: stop at once, whatever the path.
  cm.setObstacles({{4.0, 2.1}});
  EXPECT_NEAR(tn::sweptObstacleDistance(cm, fp, start, {}, 0, 2.5, false), 0.0, 1e-9);
  // An obstacle under a mapped wall's cell is the wall; unknown-space points far from walls are obstacles.
  thorvald_map::OccupancyGrid map = scene.map;
  for (int y = 100; y < 120; ++y)
    for (int x = 0; x < 40; ++x) map.at(x, y) = thorvald_map::kUnknown;
  tn::Costmap cm2(map, scene.keep_out, tn::CostmapParams{});
  cm2.setObstacles({{0.5, 5.5}, {3.65, 2.8}, {std::nan(""), 1.0}});
  EXPECT_EQ(cm2.obstaclePoints(), 1u);
  EXPECT_EQ(cm2.knownStructurePoints(), 1u);
  tn::CostmapParams bad;
  bad.known_structure_tolerance_m = -0.1;
  EXPECT_NE(bad.validate(), "");
}

// The greenhouse robot turns on the spot at (4.2, 2) from facing the edge to facing along it (left, 90 degrees): its
// rear (0.91 m behind base_link) swings through the quarter behind and to the right, where neither the box at the
// start nor the boxes along the path reach. An obstacle there stops the turn; one just beyond the rear's reach does
// not. The turn's samples are placed by angle, checked here over random obstacle positions on both sides of the
// rear corner's circle.
TEST(ObstacleCheck, AnObstacleInTheRearsSweepStopsATurnOnTheSpot) {
  const EdgeScene scene;
  tn::Costmap cm(scene.map, scene.keep_out, tn::CostmapParams{});
  const tn::Footprint fp = greenhouseFootprint();
  const thorvald_base::Pose2D start{4.2, 2.0, 0.0};
  const std::vector<Eigen::Vector2d> path{{4.2, 2.0}, {4.2, 3.6}};
  const double reach = fp.circumscribedRadius();  // 0.99 m: the rear corners' circle
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> bearing(-0.77 * thorvald_base::kPi, -0.73 * thorvald_base::kPi),
      inside(0.72, 0.86), outside(reach + 0.08, reach + 0.4);
  for (int trial = 0; trial < 20; ++trial) {
    const double b = bearing(rng);
    const Eigen::Vector2d dir(std::cos(b), std::sin(b));
    const Eigen::Vector2d swept = Eigen::Vector2d(start.x, start.y) + inside(rng) * dir;
    cm.setObstacles({swept});
    ASSERT_EQ(cm.obstaclePoints(), 1u);
    // Not under the box at the start nor at any point of the straight drive: only the turn meets it.
    EXPECT_EQ(cm.footprintBlocker(start, fp), tn::Blocker::kNone) << trial;
    for (double y = 2.0; y <= 3.6; y += 0.05)
      EXPECT_EQ(cm.footprintBlocker({4.2, y, thorvald_base::kPi / 2}, fp), tn::Blocker::kNone) << trial;
    EXPECT_NEAR(tn::sweptObstacleDistance(cm, fp, start, path, 1, 1.5, false), 0.0, 1e-9) << trial;
    EXPECT_TRUE(tn::turnTouches(cm, fp, {start.x, start.y}, 0.0, thorvald_base::kPi / 2, tn::Blocker::kObstacle))
        << trial;
    // Turning right instead (the other way round) the rear swings the other side: clear.
    EXPECT_FALSE(
        tn::turnTouches(cm, fp, {start.x, start.y}, 0.0, -thorvald_base::kPi / 2 + 1e-3, tn::Blocker::kObstacle));
    cm.setObstacles({Eigen::Vector2d(start.x, start.y) + outside(rng) * dir});
    EXPECT_LT(tn::sweptObstacleDistance(cm, fp, start, path, 1, 1.5, false), 0.0) << trial;
  }
  // The turn back to the goal's heading at the path's end: swept when the goal's heading is given and the end lies
  // within the distance checked. The obstacle sits where the rear swings when turning right from facing +y to facing
  // +x at (4.2, 3.6), clear of the post and of the straight drive.
  cm.setObstacles({{4.2 - 0.7, 3.6 - 0.45}});
  ASSERT_EQ(cm.obstaclePoints(), 1u);
  EXPECT_LT(tn::sweptObstacleDistance(cm, fp, start, path, 1, 2.5, false), 0.0);
  EXPECT_NEAR(tn::sweptObstacleDistance(cm, fp, start, path, 1, 2.5, false, 0.0), 1.6, 0.06);
  EXPECT_LT(tn::sweptObstacleDistance(cm, fp, start, path, 1, 1.0, false, 0.0), 0.0);  // beyond the look-ahead
  // Omnidirectional: keeps its heading along the path, turns only towards the goal's heading. Turning a quarter
  // where it stands sweeps the rear through the obstacle beside it.
  cm.setObstacles({{4.2 - 0.6, 2.0 - 0.6}});
  ASSERT_EQ(cm.obstaclePoints(), 1u);
  EXPECT_LT(tn::sweptObstacleDistance(cm, fp, start, path, 1, 2.5, true), 0.0);
  EXPECT_LT(tn::sweptObstacleDistance(cm, fp, start, path, 1, 2.5, true, 0.0), 0.0);
  EXPECT_NEAR(tn::sweptObstacleDistance(cm, fp, start, path, 1, 2.5, true, thorvald_base::kPi / 2), 0.0, 1e-9);
}

// The obstacle layer is re-inflated only around the cells a scan changed: after a sequence of scans (obstacles moved,
// lifted, laid on walls and on unknown space) every cell's cost is the one the costmap_2d rule gives from the
// distance to the nearest blocked cell, computed here by brute force.
TEST(Costmap, ObstacleUpdatesEqualInflatingAnew) {
  thorvald_map::OccupancyGrid map = roomWithBaffle();
  for (int y = 60; y < 79; ++y)
    for (int x = 150; x < 199; ++x) map.at(x, y) = thorvald_map::kUnknown;
  tn::CostmapParams cp;
  cp.known_structure_tolerance_m = 0.0;
  tn::Costmap cm(map, thorvald_map::OccupancyGrid(), cp);
  const auto& g = cm.geometry();
  auto expected = [&](int x, int y) -> int {
    if (cm.blocker(x, y) != tn::Blocker::kNone) return tn::kLethalCost;
    double d = 1e9;
    for (int by = std::max(0, y - 25); by <= std::min(g.height - 1, y + 25); ++by)
      for (int bx = std::max(0, x - 25); bx <= std::min(g.width - 1, x + 25); ++bx)
        if (cm.blocker(bx, by) != tn::Blocker::kNone) d = std::min(d, g.resolution_m * std::hypot(bx - x, by - y));
    d = static_cast<float>(d);  // as the distance field stores it
    if (d <= cp.planning_radius_m) return tn::kInscribedCost;
    if (d >= cp.inflation_radius_m) return 0;
    return static_cast<int>(std::max(1.0, 252.0 * std::exp(-cp.cost_scaling * (d - cp.planning_radius_m))));
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.0, 10.0), uy(0.0, 4.0);
  std::vector<std::vector<Eigen::Vector2d>> scans;
  for (int k = 0; k < 6; ++k) {
    std::vector<Eigen::Vector2d> pts;
    for (int i = 0; i < 3 + 4 * k; ++i) pts.emplace_back(ux(rng), uy(rng));  // some on walls and unknown cells
    pts.emplace_back(3.0 + 0.1 * k, 2.0);  // one that moves a little from scan to scan
    scans.push_back(pts);
  }
  scans.emplace_back();  // every obstacle lifted
  scans.push_back(scans[2]);
  int mismatches = 0, inflated_cells = 0;
  for (const auto& pts : scans) {
    cm.setObstacles(pts);
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) {
        const int want = expected(x, y);
        // The field's float distances may round a cell at a cost step by one.
        if (std::abs(static_cast<int>(cm.cost(x, y)) - want) > 1) {
          if (mismatches < 5)
            ADD_FAILURE() << "scan " << (&pts - &scans[0]) << " cell " << x << "," << y << " cost "
                          << int(cm.cost(x, y)) << " want " << want;
          ++mismatches;
        }
        if (want > 0 && want < tn::kInscribedCost) ++inflated_cells;
      }
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(inflated_cells, 1000);
  cm.setObstacles({{3.0, 2.0}});
  EXPECT_EQ(cm.blocker(g.cellOf({3.0, 2.0}).x(), g.cellOf({3.0, 2.0}).y()), tn::Blocker::kObstacle);
  EXPECT_EQ(cm.obstaclePoints(), 1u);
  cm.setObstacles({});
  EXPECT_EQ(cm.blocker(g.cellOf({3.0, 2.0}).x(), g.cellOf({3.0, 2.0}).y()), tn::Blocker::kNone);
  EXPECT_EQ(cm.cost(g.cellOf({3.0, 2.0}).x(), g.cellOf({3.0, 2.0}).y()), 0);
}

TEST(GridPlanner, StartInsideThePlanningRadiusCanLeave) {
  const tn::Costmap cm(roomWithBaffle(), thorvald_map::OccupancyGrid(), tn::CostmapParams{});
  const auto r = tn::planPath(cm, {0.2, 2.0}, {3.0, 2.0}, tn::PlannerParams{});
  EXPECT_TRUE(r.ok) << r.error;
}

TEST(Footprint, GeometryAndChecks) {
  const tn::Footprint fp = tn::rectangleFootprint(-0.86, 0.18, -0.34, 0.34);
  EXPECT_NEAR(fp.halfWidth(), 0.34, 1e-12);
  EXPECT_NEAR(fp.circumscribedRadius(), std::hypot(0.86, 0.34), 1e-12);
  EXPECT_EQ(fp.check(), "");
  const tn::Footprint two_points{{{0, 0}, {1, 0}}};
  EXPECT_NE(two_points.check(), "");
  const tn::Footprint flat{{{0, 0}, {1, 0}, {2, 0}}};
  EXPECT_NE(flat.check(), "");
  tn::CostmapParams bad;
  bad.inflation_radius_m = 0.1;
  EXPECT_NE(bad.validate(), "");
}

TEST(GridPlanner, PlansOnVariedHeadlandsBetweenRandomFloorPoints) {
  int planned = 0;
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    tn::testing::HeadlandOptions o;
    o.seed = seed;
    o.length_m = 12.0 + 2.0 * seed;
    const tn::testing::SyntheticHeadland world(o);
    const tn::Costmap cm(world.truthMap(0.05), thorvald_map::OccupancyGrid(), tn::CostmapParams{});
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> x(1.0, o.length_m - 1.0), y(1.0, o.depth_m - 1.0);
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector2d a(x(rng), y(rng)), b(x(rng), y(rng));
      const Eigen::Vector2i ca = cm.geometry().cellOf(a), cb = cm.geometry().cellOf(b);
      if (cm.cost(ca.x(), ca.y()) >= tn::kInscribedCost || cm.cost(cb.x(), cb.y()) >= tn::kInscribedCost) continue;
      const auto r = tn::planPath(cm, a, b, tn::PlannerParams{});
      ASSERT_TRUE(r.ok) << r.error;
      EXPECT_GE(r.length_m, (b - a).norm() - 1e-9);
      ++planned;
    }
  }
  EXPECT_GT(planned, 10);
}

}  // namespace
