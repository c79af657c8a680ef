#pragma once

#include <vector>

#include "greenhouse_rail_nav/headland_scan.h"
#include "greenhouse_rail_nav/line_extraction.h"
#include "thorvald_map/occupancy_grid.h"

namespace greenhouse_rail_nav {

/// Rear wall: the line with the most evidence of a greenhouse on one side of it, i.e. its own length plus
/// the length of the lines perpendicular (within tolerance [rad]) to it that lie within its span and
/// entirely on one side (rows and side walls). A short line on the headland (a hose, a box edge) spans few
/// rows; a side wall has the rows parallel to it. The wall at the rows' far end (seen through the paths)
/// closes the same rows from the other side and can score as much: of two walls facing each other across
/// the same lines (80 % of their length shared), the rear wall is the one that evidence lies nearer to,
/// since a headland map is made by driving on the headland and shows the rows best near it. Returns the
/// index into lines (-1 when empty) and sets *side to +1 or -1 (the rows' side of its normal).
int selectRearWall(const std::vector<LineSegment>& lines, double tolerance, double* side);

/// Where the rear wall (the line v = 0 of frame) ends beyond u_from, walking outwards (direction -1: left,
/// +1: right) along its cells (a band of +-0.15 m about its line, gaps up to 0.3 m bridged) [m, headland u];
/// *floor_beyond says whether floor is mapped in front of the headland beyond that end (the wall ends there,
/// rather than the map). NaN when no wall cell is met or the walk reaches max_travel_m.
double rearWallEnd(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, double u_from, double direction,
                   double max_travel_m, bool* floor_beyond);

}  // namespace greenhouse_rail_nav
