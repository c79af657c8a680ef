#pragma once
// The stages of the headland map analysis after the rows are found (analyzeMap in map_analyzer.h calls them
// in this order): side walls, edge straightness, row headings, the rear wall's ends, the greenhouse's heading,
// the spacing fit, the checks, the sides' bounds, rail-set placement and the report.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "greenhouse_rail_nav/headland_rows.h"
#include "greenhouse_rail_nav/headland_scan.h"
#include "greenhouse_rail_nav/line_extraction.h"
#include "greenhouse_rail_nav/map_analyzer.h"
#include "greenhouse_rail_nav/rail_set_layout.h"
#include "greenhouse_rail_nav/rail_spacing.h"

namespace greenhouse_rail_nav {

/// "a; b; c".
std::string joinReasons(const std::vector<std::string>& reasons);

/// The headland frame of a rear wall: origin at its centroid, v its normal into the rows (side: the sign
/// selectRearWall gave), u to the right looking into the rows.
HeadlandFrame headlandFrameOf(const LineFit2D& wall, double side);

/// An outermost line (rows sorted by u) with no floor mapped beyond it (floor_extent_m < 0.3 m) is the side
/// wall itself, seen through a door: it leaves the rows (when at least two remain) and its inner face
/// becomes that side's wall. Sides where a wall was already found are left alone.
void takeOuterLinesAsSideWalls(SideScan* left, SideScan* right, std::vector<EdgeRow>* rows);

/// How straight the headland edge is from the row starts on it.
struct EdgeStraightness {
  double rms_m = INFINITY;  ///< RMS of the row starts about the edge [m] (infinite: no start on it)
  int rows_at_edge = 0;     ///< rows whose start lies on the edge
};

/// Row starts farther than 2 * straightness_m from edge_v [m] are named in *warnings and left out.
EdgeStraightness measureEdgeStraightness(const std::vector<EdgeRow>& rows, double edge_v, double straightness_m,
                                         std::vector<std::string>* warnings);

/// Sets each row's heading_ok: its direction within tolerance_rad of rows_mean plus what a cell
/// (resolution_m [m]) and the row's scatter allow over its length. Returns the rows off heading.
int judgeRowHeadings(std::vector<EdgeRow>* rows, const Eigen::Vector2d& rows_mean, double resolution_m,
                     double tolerance_rad);

/// The rear wall's end beyond the outermost row on a side without a side wall.
struct RearWallEnd {
  bool usable = false;    ///< found, floor mapped beyond it, and beyond the row
  double end_u = NAN;     ///< [m, headland u]
  double distance = 0.0;  ///< from the outermost row outwards [m]
};

RearWallEnd findRearWallEnd(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, const SideScan& side,
                            double outer_u, double direction, double max_travel_m);

/// The greenhouse's heading [rad, map]: every straight piece along its axis weighted by inverse variance of
/// its direction: the rear wall's normal, the rows, and lines along rows_mean (within
/// perpendicular_tolerance_rad) meeting the edge (edge_v) within 0.3 m of a found side wall.
double greenhouseHeading(const std::vector<LineSegment>& lines, int rear_wall, const HeadlandFrame& frame,
                         const std::vector<EdgeRow>& rows, const Eigen::Vector2d& rows_mean, const SideScan& left,
                         const SideScan& right, double edge_v, double perpendicular_tolerance_rad, double resolution_m);

/// The lines across the headland, the gaps between them and the spacing that fits them.
struct SpacingFit {
  std::vector<HeadlandBoundary> bounds;  ///< left wall, rows, right wall, in order of u
  std::vector<double> gaps;              ///< between neighbouring bounds [m]
  SpacingEstimate estimate;
  double fit_tolerance_m = 0.0;
  double spacing_m = 0.0;  ///< the measured spacing, or the configured one without a gap [m]
};

SpacingFit fitSpacing(const SideScan& left, const std::vector<EdgeRow>& rows, const SideScan& right,
                      const MapAnalyzerParams& params, double resolution_m);

/// The outcome of the checks that concern the whole map.
struct GlobalChecks {
  bool wall = false, edge = false, heading = false, spacing_regular = false, spacing_unique = false,
       spacing_confirmed = false;
};

/// Appends rear_wall_spans_rows, edge_straight, rows_agree_in_heading, each_row_parallel, spacing_regular,
/// spacing_unambiguous and spacing_confirmed to *checks.
GlobalChecks checkLayout(double wall_length_m, const std::vector<EdgeRow>& rows, const EdgeStraightness& edge,
                         double rows_vs_wall_rad, int rows_off_heading, const SpacingFit& fit,
                         const MapAnalyzerParams& params, double resolution_m, std::vector<AnalysisCheck>* checks);

/// Rail sets between the outermost row and the rear wall's end: a whole number of spacings with at most
/// max_thickness_m [m] left for the corner's wall, on a regular, unique, confirmed pattern; -1 when none.
int setsToRearWallEnd(const RearWallEnd& end, const SpacingFit& fit, bool spacing_confirmed, double max_thickness_m);

/// Sets per side placed up to the rear wall's end (-1: none).
struct SideBounds {
  int left_end_sets = -1, right_end_sets = -1;
};

/// Bounds each side by its wall or the rear wall's end, sets the result's *_by_rear_wall_end flags, appends
/// the sides_bounded check and a warning per side bounded by the rear wall's end.
SideBounds boundSides(const SideScan& left, const SideScan& right, const RearWallEnd& left_end,
                      const RearWallEnd& right_end, const SpacingFit& fit, bool spacing_confirmed,
                      double max_thickness_m, MapAnalysis* result);

/// Rail frames and target poses of the planned sets on the edge (edge_v), each good when neither
/// global_reasons nor its own give a reason. Appends to result->rail_sets; returns the good ones.
int placeRailSets(const std::vector<RailSetPlan>& plans, const HeadlandFrame& frame, double edge_v, double heading,
                  const thorvald_base::Pose2D& target_in_rail, const std::vector<std::string>& global_reasons,
                  MapAnalysis* result);

/// Status, confidence and uncertain_reasons from the checks, the sets (good of them good) and the reasons.
void judgeAnalysis(int good, int rows_off_heading, const std::vector<std::string>& global_reasons,
                   const SpacingFit& fit, MapAnalysis* result);

}  // namespace greenhouse_rail_nav
