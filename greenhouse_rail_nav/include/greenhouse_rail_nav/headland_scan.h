#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "thorvald_map/occupancy_grid.h"

namespace greenhouse_rail_nav {

/// The headland frame: origin on the rear wall line, u along it (to the right looking into the rows),
/// v from the rear wall into the rows.
struct HeadlandFrame {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero(), u = Eigen::Vector2d::UnitX(), v = Eigen::Vector2d::UnitY();
  Eigen::Vector2d toLocal(const Eigen::Vector2d& p) const { return {u.dot(p - origin), v.dot(p - origin)}; }
  Eigen::Vector2d toMap(double pu, double pv) const { return origin + pu * u + pv * v; }
};

/// Where a row (a line along v at u = u0 + slope * v) has its runs: stretches where the map shows a row
/// (occupied cells within row_half_width_m of the line and nothing wider, up to clutter_reach_m, beside
/// it) without a gap longer than max_gap_m. Anything wider than a row (a box or trolley in line with it)
/// breaks a run, so a run starts where the row itself does. Returns the v of each run's start [m] for runs
/// of at least min_run_m, and *far_v the largest v showing the row.
std::vector<double> rowRunStarts(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, double u0,
                                 double slope, double v_from, double v_to, double* far_v, double row_half_width_m = 0.2,
                                 double clutter_reach_m = 0.5, double max_gap_m = 0.3, double min_run_m = 0.4);

/// How a row shows across its width over its first metres: where its two faces are, from the stations
/// along it where the map saw free floor right beyond its outermost occupied cell. A row seen from one
/// side only (a ventilation tube seen from one path) has cells on that face alone; their mean is off the
/// row's centre by half its width, so the centre comes from the faces, never from the cells' mean.
struct RowProfile {
  int cells = 0;                            ///< occupied cells in the band
  double mean_m = 0.0;                      ///< mean lateral offset of those cells [m]
  double d_min = 0.0, d_max = 0.0;          ///< lateral extent of the cells (centres) [m]
  int lo_stations = 0, hi_stations = 0;     ///< stations whose low / high face was seen with floor beyond it
  double lo_face_m = 0.0, hi_face_m = 0.0;  ///< median lateral offset of each seen face (cell centres) [m]
  double slope = 0.0;                       ///< the faces' lateral drift per metre along (beyond the row's front)
  double slope_sigma = INFINITY;            ///< standard error of slope (infinite: too few stations)
  int stations = 0;                         ///< stations with any cell of the row
  /// A face counts as seen at a twentieth of the stations and at least 3 (a stray cell is no face).
  bool loSeen() const { return lo_stations >= std::max(3, stations / 20); }
  bool hiSeen() const { return hi_stations >= std::max(3, stations / 20); }
  bool bothFaces() const { return loSeen() && hiSeen(); }
};

/// Measures a row from `start` (a point near its front, on its line) over [-0.05, length_m] along `along`
/// (unit) and within half_width_m across it; lateral offsets are along (along.y, -along.x).
RowProfile measureRowProfile(const thorvald_map::OccupancyGrid& map, const Eigen::Vector2d& start,
                             const Eigen::Vector2d& along, double half_width_m, double length_m);

/// Result of scanlines across the headland from the outermost row outwards.
struct SideScan {
  bool wall_found = false;
  double wall_u = 0.0;  ///< inner face of the side wall [m, headland u]
  int scanlines = 0;
  int at_wall = 0;              ///< scanlines stopping at the wall (occupied or through a door into unknown)
  int beyond_wall = 0;          ///< scanlines going on past it
  double floor_extent_m = 0.0;  ///< median distance the scanlines travel from the start before stopping [m]
};

/// Many scanlines across the headland (between the rear wall and the edge) from u_start outwards
/// (direction -1: left, +1: right), each walking on through obstacles that have floor behind them (boxes,
/// hoses, noise) and stopping where the mapped floor ends (the face after the last free cell). A side
/// wall is the farthest place where at least min_support of the scanlines stop at an occupied cell
/// together (a door lets some into unknown space at the same place) and almost none go on beyond.
/// max_travel_m bounds each walk. With the map's cell surface (thorvald_map::OccupancyGrid::surface) a stop at an
/// occupied cell is moved to the mean of the beam ends around it: the wall's face inside its cells.
SideScan scanToSideWall(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, double u_start,
                        double edge_v, double direction, double min_support, double max_travel_m);

}  // namespace greenhouse_rail_nav
