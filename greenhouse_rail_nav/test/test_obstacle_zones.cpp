// The protected zone's logic (obstacle_zones.h) on synthetic scans of a row: the far wall at the rail set's length is
// the end, a person or a crate short of it is an obstacle and never the end; on the headland people that are not in
// the map and near the robot are in the zone; reversing, the rear range finders.
#include <gtest/gtest.h>

#include <cmath>

#include "greenhouse_rail_nav/lit_coverage.h"
#include "greenhouse_rail_nav/obstacle_zones.h"

namespace grn = greenhouse_rail_nav;

namespace {

constexpr double kLidarX = 0.45;

/// A scan from a lidar at (kLidarX, 0) over ±135°: a wall across x = wall_x (|y| < 0.8), and circles (people) or
/// boxes seen as their near face, each hiding what lies behind it.
struct SyntheticScan {
  double wall_x = 21.0;
  struct Body {
    double x, y, half_width;
    bool round = false;  ///< a person (circle of radius half_width about x, y), else a flat face at x - half_width
  };
  std::vector<Body> bodies;

  std::vector<grn::ScanPoint> points() const {
    std::vector<grn::ScanPoint> pts;
    for (int i = 0; i <= 1080; ++i) {
      const double a = -2.356 + i * (4.712 / 1080);
      const double c = std::cos(a), s = std::sin(a);
      double r = INFINITY;
      if (c > 1e-6) {
        const double rw = (wall_x - kLidarX) / c;
        if (std::fabs(rw * s) < 0.8) r = rw;
      }
      for (const Body& b : bodies) {
        if (b.round) {  // nearest hit of the ray on the circle (behind the lidar too)
          const double dx = b.x - kLidarX, along = dx * c + b.y * s, miss2 = dx * dx + b.y * b.y - along * along;
          const double h2 = b.half_width * b.half_width - miss2;
          if (h2 >= 0.0 && along - std::sqrt(h2) > 0.0) r = std::min(r, along - std::sqrt(h2));
          continue;
        }
        if (c <= 1e-6) continue;
        const double rb = (b.x - b.half_width - kLidarX) / c;
        if (std::fabs(rb * s - b.y) <= b.half_width && rb < r) r = rb;
      }
      if (std::isfinite(r) && r < 30.0) pts.push_back({kLidarX + r * c, r * s});
    }
    return pts;
  }
};

grn::ZoneContext row(double row_end_m) {
  grn::ZoneContext c;
  c.phase = grn::ZonePhase::kRow;
  c.row_end_m = row_end_m;
  return c;
}

/// The first of `scans` identical scans at which the confirmed row verdict holds the robot (0: none does); its
/// verdict in `last`.
int firstHoldingScan(const SyntheticScan& scan, const grn::ZoneContext& ctx, const grn::ZoneParams& p, int scans,
                     grn::ZoneVerdict* last) {
  grn::PersonConfirmation confirm(p);
  for (int k = 1; k <= scans; ++k) {
    *last = grn::evaluateZone(scan.points(), kLidarX, ctx, p);
    confirm.apply(ctx.phase, last);
    if (last->blocked) return k;
  }
  return 0;
}

}  // namespace

TEST(ObstacleZones, APersonSizedClusterIsAPerson) {
  grn::ZoneParams p;
  SyntheticScan scan;
  scan.bodies.push_back({4.0, 0.0, 0.25, true});  // a person, 0.5 m across
  const auto clusters = grn::clusterScan(scan.points(), p, kLidarX);
  ASSERT_GE(clusters.size(), 1u);  // the person (hiding the wall)
  bool person = false;
  for (const auto& c : clusters)
    if (std::fabs(c.x - 3.85) < 0.15) person = c.person;
  EXPECT_TRUE(person);
  // The wall (1.6 m across) is too wide to be one.
  SyntheticScan wall_only;
  const auto w = grn::clusterScan(wall_only.points(), p, kLidarX);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_FALSE(w[0].person);
}

TEST(ObstacleZones, MixedPixelsAlongTheBeamsAndAPipeEndAreNoPerson) {
  grn::ZoneParams p;
  // Five returns along one beam between an edge 1.0 m away and the wall 1.6 m away (mixed pixels).
  std::vector<grn::ScanPoint> streak;
  for (int i = 0; i < 5; ++i) streak.push_back({kLidarX + 1.0 + 0.12 * i, 0.3 + 0.036 * i});
  auto c = grn::clusterScan(streak, p, kLidarX);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_FALSE(c[0].person) << c[0].width;
  // The end of a 0.16 m heating line seen head-on 1.1 m away.
  SyntheticScan pipe;
  pipe.wall_x = 30.0;
  pipe.bodies.push_back({1.1, 0.0, 0.08, true});
  c = grn::clusterScan(pipe.points(), p, kLidarX);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_FALSE(c[0].person) << c[0].width;
}

TEST(ObstacleZones, TheWallAtTheSetsLengthIsTheEnd) {
  grn::ZoneParams p;
  SyntheticScan scan;  // rails of 20 m, wall 1 m beyond their end; base_link 18 m along: the end 2 m ahead
  const grn::ZoneVerdict v = grn::evaluateZone(scan.points(), kLidarX, row(2.0), p);
  EXPECT_FALSE(v.blocked) << v.why;
  EXPECT_NEAR(v.end_range_m, 21.0 - kLidarX, 0.01);
}

// A person standing at the far end of the row, within the end's tolerance of the set's length, is a person, not the
// end: the robot would otherwise drive at them with its lamps on until the far wall's guard stopped it.
TEST(ObstacleZones, APersonAtTheRowsFarEndIsNoEnd) {
  grn::ZoneParams p;
  SyntheticScan scan;  // the end 5 m ahead (end tolerance 1 m), the wall 1 m beyond it, a person 0.5 m short of it
  scan.wall_x = 6.0;
  scan.bodies.push_back({4.5, 0.0, 0.25, true});
  const grn::ZoneVerdict v = grn::evaluateZone(scan.points(), kLidarX, row(5.0), p);
  EXPECT_TRUE(v.blocked);
  EXPECT_TRUE(v.person);
  EXPECT_NE(v.why.find("a person in the row ahead"), std::string::npos) << v.why;
  // From 40 m away a person there is a few returns that cannot be told from the wall: the end, until the robot is
  // near enough (about 10 m) to see them with 10 returns.
  SyntheticScan far;
  far.wall_x = 40.0;
  far.bodies.push_back({39.5, 0.0, 0.25, true});
  EXPECT_FALSE(grn::evaluateZone(far.points(), kLidarX, row(40.0), p).blocked);
  // Nor is the far wall 1 m beyond the rails' end a person, whatever its few returns fit.
  SyntheticScan wall;
  wall.wall_x = 21.0;
  for (double y = -0.3; y <= 0.3; y += 0.06) wall.bodies.push_back({21.0 - 0.05 * (1.0 - y * y / 0.09), y, 0.03, true});
  EXPECT_FALSE(grn::evaluateZone(wall.points(), kLidarX, row(20.0), p).blocked);
}

TEST(ObstacleZones, ACrateShortOfTheEndIsAnObstacleNeverTheEnd) {
  grn::ZoneParams p;
  SyntheticScan scan;
  scan.wall_x = 23.0;
  scan.bodies.push_back({6.0, 0.0, 0.2});  // a crate 0.4 m across, 6 m ahead, in a row that ends 20 m ahead
  const grn::ZoneVerdict v = grn::evaluateZone(scan.points(), kLidarX, row(20.0), p);
  EXPECT_TRUE(v.blocked);
  EXPECT_TRUE(std::isnan(v.end_range_m)) << "a return short of the set's length is never the end";
  EXPECT_NE(v.why.find("row ahead"), std::string::npos) << v.why;
}

TEST(ObstacleZones, APersonInTheRowIsAPersonInTheZone) {
  grn::ZoneParams p;
  SyntheticScan scan;
  scan.bodies.push_back({10.0, 0.05, 0.25, true});
  const grn::ZoneVerdict v = grn::evaluateZone(scan.points(), kLidarX, row(19.0), p);
  EXPECT_TRUE(v.blocked);
  EXPECT_TRUE(v.person);
  EXPECT_NE(v.why.find("person"), std::string::npos) << v.why;
}

// A person stepping into the corridor 9.6 m ahead, where the beams are 4 cm apart: the cluster the band beside the
// corridor completes holds the robot as the body's edge crosses the side; with only the points inside counting
// (row_edge_band 0), it takes min_cluster_points returns inside, the body some 10 cm in. A body whose edge stays
// outside the side does not hold.
TEST(ObstacleZones, APersonSteppingIntoTheCorridorHoldsAsTheirEdgeCrossesTheSide) {
  const double radius = 0.2, side = grn::ZoneParams().row_half_width_m;
  const auto depth_at_hold = [&](const grn::ZoneParams& p) {
    for (double depth = -0.05; depth <= 0.3; depth += 0.0025) {  // how far the body's edge is inside the side
      SyntheticScan scan;
      scan.bodies.push_back({9.6, side + radius - depth, radius, true});
      if (grn::evaluateZone(scan.points(), kLidarX, row(19.0), p).blocked) return depth;
    }
    return 1.0;
  };
  grn::ZoneParams banded;
  ASSERT_GT(banded.row_edge_band_m, 0.0);
  grn::ZoneParams inside_only;
  inside_only.row_edge_band_m = 0.0;
  const double with_band = depth_at_hold(banded), without = depth_at_hold(inside_only);
  EXPECT_GT(with_band, 0.0) << "a body outside the corridor held the robot";
  EXPECT_LE(with_band, 0.045) << "one beam spacing at 9.6 m is 4.2 cm";
  EXPECT_GT(without, with_band + 0.03) << "with " << with_band << " m, without " << without << " m";
  EXPECT_LT(without, 0.3);
}

// Treating, the lamps light the plants beside the rails: a person standing in the plant row 0.8 m beside the robot is
// in the zone once seen in person_confirm_scans scans, while anything in the corridor ahead still blocks at once. Not
// while entering (lamps off), and not a person in the next row, whose centre is 1.9 m away.
TEST(ObstacleZones, TreatingAPersonBesideTheRobotInTheLampsReachHoldsOnceConfirmed) {
  grn::ZoneParams p;
  ASSERT_EQ(p.person_confirm_scans, 3);
  grn::ZoneContext treating = row(19.0);
  treating.lamps = true;
  grn::ZoneVerdict v;
  SyntheticScan beside;
  beside.bodies.push_back({0.8, 0.8, 0.25, true});
  EXPECT_EQ(firstHoldingScan(beside, treating, p, 5, &v), 3);
  EXPECT_TRUE(v.person);
  EXPECT_NE(v.why.find("beside the robot"), std::string::npos) << v.why;
  // Entering the rails (lamps off) the same person is no reason to hold.
  EXPECT_EQ(firstHoldingScan(beside, row(19.0), p, 5, &v), 0) << v.why;
  // A person standing between the next set's rails, 1.6 m to the side.
  SyntheticScan next_row;
  next_row.bodies.push_back({0.8, 1.6, 0.25, true});
  EXPECT_EQ(firstHoldingScan(next_row, treating, p, 5, &v), 0) << v.why;
  // The corridor is not delayed by the confirmation: a person 10 m ahead blocks at the first scan.
  SyntheticScan ahead;
  ahead.bodies.push_back({10.0, 0.05, 0.25, true});
  EXPECT_EQ(firstHoldingScan(ahead, treating, p, 5, &v), 1);
  EXPECT_NE(v.why.find("in the row ahead"), std::string::npos) << v.why;
  // Beside the rails' start and the row's end the ventilation lines' round caps stand where a person would: nobody is
  // watched there (row_ends_margin).
  grn::ZoneContext at_end = row(0.8);
  at_end.lamps = true;
  EXPECT_EQ(firstHoldingScan(beside, at_end, p, 5, &v), 0) << v.why;
  SyntheticScan behind_beside;
  behind_beside.bodies.push_back({-0.25, 0.8, 0.25, true});
  grn::ZoneContext at_start = treating;
  at_start.row_along_m = 0.3;
  EXPECT_EQ(firstHoldingScan(behind_beside, at_start, p, 5, &v), 0) << v.why;
  at_start.row_along_m = 3.0;
  EXPECT_EQ(firstHoldingScan(behind_beside, at_start, p, 5, &v), 3) << "3 m into the row the same person is watched";
  // With row_lamps_radius 0 the check is off.
  p.row_lamps_radius_m = 0.0;
  EXPECT_EQ(firstHoldingScan(beside, treating, p, 5, &v), 0) << v.why;
}

// A robot turned 4 degrees on the rails (a wheel jolted at an open pipe joint) sees the ventilation line beside the
// row, 0.8 m to its right at the lidar's height, cross its corridor ahead: a straight line along the row is the
// greenhouse's, not an obstacle nor the far end; a person standing against that line still is one.
TEST(ObstacleZones, ALineAlongTheRowIsNoObstacleForARobotTurnedOnTheRails) {
  grn::ZoneParams p;
  const double yaw = -0.07;  // the robot's heading against the rails
  // Returns every 0.25 deg from a lidar at (kLidarX, 0) on a line at y = -0.8 (rail frame) from x = 1 to 20, and on
  // the far wall at x = 20.4, both seen in the turned robot's frame; the line's glancing returns are lost beyond 11 m.
  auto scan = [&](bool person) {
    std::vector<grn::ScanPoint> pts;
    const double c = std::cos(yaw), s = std::sin(yaw);
    for (int i = 0; i <= 1080; ++i) {
      const double a = -2.356 + i * (4.712 / 1080);
      const double dx = std::cos(a + yaw), dy = std::sin(a + yaw);  // the beam in the rail frame
      const double ox = kLidarX * c, oy = kLidarX * s;              // the lidar in the rail frame
      double r = INFINITY;
      if (dy < -1e-6) {  // the line y = -0.8
        const double t = (-0.8 - oy) / dy, x = ox + t * dx;
        if (x > 1.0 && x < 20.0 && t < 11.0) r = t;
      }
      if (dx > 1e-6) {  // the far wall, |y| < 0.8
        const double t = (20.4 - ox) / dx;
        if (std::fabs(oy + t * dy) < 0.8) r = std::min(r, t);
      }
      if (person && dx > 1e-6) {  // a person of radius 0.2 at (6, -0.45): in the corridor, against the line
        const double px = 6.0 - ox, py = -0.45 - oy, along = px * dx + py * dy;
        const double h2 = 0.04 - (px * px + py * py - along * along);
        if (h2 >= 0.0) r = std::min(r, along - std::sqrt(h2));
      }
      if (std::isfinite(r)) pts.push_back({kLidarX + r * std::cos(a), r * std::sin(a)});
    }
    return pts;
  };
  const grn::ZoneContext ctx = row(19.4);  // base_link 1 m along a 20.4 m set
  const auto empty = scan(false);
  const std::vector<bool> structure = grn::rowStructure(empty, p);
  int on_line = 0, in_corridor = 0;
  for (std::size_t i = 0; i < empty.size(); ++i) {
    on_line += structure[i];
    in_corridor += empty[i].x > 0.0 && std::fabs(empty[i].y) < p.row_half_width_m && empty[i].x < 15.0;
  }
  EXPECT_GT(in_corridor, 5) << "the turned robot sees the line in its corridor";
  EXPECT_GT(on_line, 50);
  grn::ZoneVerdict v = grn::evaluateZone(empty, kLidarX, ctx, p);
  EXPECT_FALSE(v.blocked) << v.why;
  EXPECT_NEAR(v.end_range_m, 20.4 - kLidarX, 0.3) << "the far wall is still the end";
  grn::ZoneParams off = p;
  off.structure_min_length_m = 0.0;
  EXPECT_TRUE(grn::evaluateZone(empty, kLidarX, ctx, off).blocked) << "without the rule the line blocks";
  v = grn::evaluateZone(scan(true), kLidarX, ctx, p);
  EXPECT_TRUE(v.blocked);
  EXPECT_TRUE(v.person) << v.why;
}

TEST(ObstacleZones, WithoutTheSetsLengthAnyReturnAheadIsTheEnd) {
  // As before issue 29: the length unknown, the crate ends the row (the legacy behaviour, documented as unsafe).
  grn::ZoneParams p;
  SyntheticScan scan;
  scan.bodies.push_back({6.0, 0.0, 0.2});
  const grn::ZoneVerdict v = grn::evaluateZone(scan.points(), kLidarX, row(0.0), p);
  EXPECT_FALSE(v.blocked);
  EXPECT_NEAR(v.end_range_m, 5.8 - kLidarX, 0.01);
}

TEST(ObstacleZones, HeadlandPeopleNotInTheMapAndNearAreInTheZone) {
  grn::ZoneParams p;
  grn::ZoneContext c;
  c.phase = grn::ZonePhase::kHeadland;
  SyntheticScan near;
  near.wall_x = 8.0;
  near.bodies.push_back({1.2, 0.3, 0.25, true});
  // The wall is part of the map.
  const grn::KnownPoint known = [](double x, double) { return x > 7.5; };
  grn::ZoneVerdict v = grn::evaluateZone(near.points(), kLidarX, c, p, known);
  EXPECT_TRUE(v.blocked);
  EXPECT_TRUE(v.person);
  SyntheticScan far;
  far.wall_x = 8.0;
  far.bodies.push_back({3.5, 0.3, 0.25, true});
  v = grn::evaluateZone(far.points(), kLidarX, c, p, known);
  EXPECT_FALSE(v.blocked) << "a person 3.5 m away is outside the headland radius: " << v.why;
  // A trolley's flat 0.6 m face near the robot on the headland is no person: left to the navigator.
  SyntheticScan trolley;
  trolley.wall_x = 8.0;
  trolley.bodies.push_back({1.2, 0.0, 0.3});
  v = grn::evaluateZone(trolley.points(), kLidarX, c, p, known);
  EXPECT_FALSE(v.blocked) << v.why;
}

// Reversing out of a set onto the headland, the lidar looks into the rows: the round end of a ventilation line under
// the plant row beside the set (x = 0 to 0.16 m past the edge, 0.8 m to the side) is a person-sized round cluster
// the headland map holds as free floor (the lidar's plane passes over the line when mapping). The map analyzer's
// keep-out zone beyond the edge is not headland: nobody is there for the headland zone.
TEST(ObstacleZones, TheRowsBeyondTheHeadlandEdgeAreNotHeadland) {
  // Map frame: the headland x < 0, the rows x >= 0; 5 cm cells, all free floor but a wall at x = -5.
  thorvald_map::OccupancyGrid map(200, 120, 0.05, -6.0, -3.0, thorvald_map::kFree);
  for (int y = 0; y < 120; ++y) map.at(20, y) = thorvald_map::kOccupied;
  thorvald_map::OccupancyGrid keep_out(40, 24, 0.25, -6.0, -3.0, thorvald_map::kFree);
  for (int y = 0; y < 24; ++y)
    for (int x = 24; x < 40; ++x) keep_out.at(x, y) = thorvald_map::kOccupied;  // x >= 0
  EXPECT_FALSE(grn::notHeadland(map, keep_out, 4, {-1.0, 0.8}));
  EXPECT_TRUE(grn::notHeadland(map, keep_out, 4, {0.1, 0.8}));
  EXPECT_TRUE(grn::notHeadland(map, keep_out, 4, {-4.9, 0.0}));  // within reach of the wall
  EXPECT_TRUE(grn::notHeadland(map, keep_out, 4, {20.0, 0.0}));  // outside the map
  EXPECT_FALSE(grn::notHeadland(map, {}, 4, {0.1, 0.8}));        // no keep-out grid: the map alone
  // The robot reversing at x = -1.0 (base_link at the origin of the scan, facing +x): the vent line's end.
  grn::ZoneParams p;
  grn::ZoneContext c;
  c.phase = grn::ZonePhase::kReverse;
  c.reverse_left_m = 0.5;
  SyntheticScan vent;
  vent.wall_x = 25.0;
  vent.bodies.push_back({1.25, 0.8, 0.2, true});  // the end cap and the line's side: round, person-sized, x > 0.05
  const double base_x = -1.0;
  auto known = [&](const thorvald_map::OccupancyGrid& k) {
    return grn::KnownPoint([&map, &k, base_x](double x, double y) {
      return grn::notHeadland(map, k, 4, {base_x + x, y});
    });
  };
  grn::ZoneVerdict v = grn::evaluateZone(vent.points(), kLidarX, c, p, known({}));
  EXPECT_TRUE(v.person) << "without the keep-out zone the vent's end reads as a person";
  v = grn::evaluateZone(vent.points(), kLidarX, c, p, known(keep_out));
  EXPECT_FALSE(v.blocked) << v.why;
  // A person on the headland beside the robot still is one.
  SyntheticScan person = vent;
  person.bodies = {{0.7, -0.9, 0.2, true}};
  v = grn::evaluateZone(person.points(), kLidarX, c, p, known(keep_out));
  EXPECT_TRUE(v.person) << v.why;
}

TEST(ObstacleZones, ReversingTheRearRangeFindersWatchBehind) {
  grn::ZoneParams p;
  grn::ZoneContext c;
  c.phase = grn::ZonePhase::kReverse;
  EXPECT_FALSE(grn::evaluateZone({}, kLidarX, c, p, {}, {NAN, 2.5}).blocked);
  const grn::ZoneVerdict v = grn::evaluateZone({}, kLidarX, c, p, {}, {NAN, 0.6});
  EXPECT_TRUE(v.blocked);
  EXPECT_NE(v.why.find("behind"), std::string::npos);
  c.phase = grn::ZonePhase::kHeadland;
  EXPECT_FALSE(grn::evaluateZone({}, kLidarX, c, p, {}, {0.6}).blocked) << "only while reversing";
}

TEST(ObstacleZones, ReversingSomethingBehindHoldsOnlyWithinTheRestOfTheWayAndTheClearance) {
  grn::ZoneParams p;  // rear_stop_range 1.0 m, rear_clearance 0.3 m
  grn::ZoneContext c;
  c.phase = grn::ZonePhase::kReverse;
  c.reverse_left_m = 0.5;  // the robot reverses at most 0.5 m more: within 0.8 m is in its way
  EXPECT_FALSE(grn::evaluateZone({}, kLidarX, c, p, {}, {0.9, NAN}).blocked)
      << "a trolley parked 0.9 m behind where the robot stops holds it for good";
  EXPECT_TRUE(grn::evaluateZone({}, kLidarX, c, p, {}, {0.75, NAN}).blocked);
  c.reverse_left_m = 0.0;
  EXPECT_TRUE(grn::evaluateZone({}, kLidarX, c, p, {}, {NAN, 0.25}).blocked) << "closer than the clearance";
  EXPECT_FALSE(grn::evaluateZone({}, kLidarX, c, p, {}, {NAN, 0.35}).blocked);
  c.reverse_left_m = 5.0;  // far to go: rear_stop_range decides
  EXPECT_TRUE(grn::evaluateZone({}, kLidarX, c, p, {}, {0.95}).blocked);
  EXPECT_FALSE(grn::evaluateZone({}, kLidarX, c, p, {}, {1.05}).blocked);
  c.reverse_left_m = -1.0;  // unknown
  EXPECT_TRUE(grn::evaluateZone({}, kLidarX, c, p, {}, {0.9}).blocked);
}

TEST(ObstacleZones, TheHoldLastsUntilTheZoneWasClearForTheClearTime) {
  grn::ZoneHold hold(2.0);
  EXPECT_FALSE(hold.update(false, 0.0));
  EXPECT_TRUE(hold.update(true, 1.0));
  EXPECT_TRUE(hold.update(false, 1.5));
  EXPECT_TRUE(hold.update(false, 2.9));
  EXPECT_FALSE(hold.update(false, 3.0));
}

TEST(LitCoverage, AStretchBrakedThroughWithTheLightsOffIsAGapUntilLitAgain) {
  grn::LitCoverage lit(0.05);
  lit.add(0.0, 5.0, true);
  lit.add(5.0, 5.3, false);  // braking with the lights off
  EXPECT_NEAR(lit.litUpTo(), 5.0, 0.051);
  EXPECT_LT(lit.fraction(), 0.99);
  lit.add(5.3, 4.9, false);  // back over it
  lit.add(4.9, 10.0, true);
  EXPECT_DOUBLE_EQ(lit.fraction(), 1.0);
  EXPECT_NEAR(lit.litUpTo(), 10.0, 1e-9);
}
