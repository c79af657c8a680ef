#pragma once

#include <string>
#include <vector>

#include "greenhouse_rail_nav/line_fit.h"
#include "thorvald_base/pose2d.h"

namespace greenhouse_rail_nav {

/// One rail seen from base_link: its line and the along-line positions of its points.
struct RailLine {
  LineFit2D fit;        ///< direction oriented away from the robot (+x of base_link)
  double near_end = 0;  ///< along-line position of the rail's start, relative to fit.centroid [m]
  std::size_t points = 0;
  double height_m = 0.0;  ///< median height of the rail's points above base_link [m]
};

/// A rail set found from two rails: the rail frame in base_link (origin between the rails at their
/// start, x along the rails).
struct RailPair {
  RailLine first, second;
  thorvald_base::Pose2D rail_in_base;
  double gauge_m = 0.0;  ///< measured distance between the two rail lines [m]
};

/// Builds a RailLine from points (x, y in base_link): least-squares line, oriented forward, its near end the
/// first along-line position from which min_run points follow without a gap above max_gap_m [m], so a stray
/// point in front of the rail cannot move it (nor does the rail's length).
RailLine makeRailLine(const std::vector<Eigen::Vector2d>& points, double max_gap_m = 0.05, std::size_t min_run = 4);

/// Refits a rail on the points within trim_m of its line, then within trim_m / 2 of the new line, so
/// a leaf touching the rail's cluster does not pull the line sideways. Keeps rail's linearity (the
/// untrimmed cluster's fit quality, used for ranking).
RailLine trimRailLine(const std::vector<Eigen::Vector2d>& points, const RailLine& rail, double trim_m);

/// Share [0, 1] of bin_m long bins along the line, between its extremes, that hold at least one point:
/// close to 1 for a pipe seen end to end, lower for leaves that happen to line up.
double lineCoverage(const std::vector<Eigen::Vector2d>& points, const LineFit2D& line, double bin_m);

/// The rail frame between two roughly parallel rails: heading from the point-weighted mean direction,
/// origin on the centre line at the nearer of the two rails' near ends.
RailPair makeRailPair(const RailLine& a, const RailLine& b);

}  // namespace greenhouse_rail_nav
