#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "greenhouse_rail_nav/headland_scan.h"
#include "greenhouse_rail_nav/line_extraction.h"
#include "greenhouse_rail_nav/map_analyzer.h"
#include "thorvald_map/occupancy_grid.h"

namespace greenhouse_rail_nav {

/// A line across the headland that may be a row: where it crosses the headland, its direction and the
/// places where a row-like run of it starts.
struct RowCandidate {
  int line = -1;
  double u0 = 0.0, slope = 0.0;  ///< the line as u = u0 + slope * v (headland frame)
  std::vector<double> starts;    ///< v of each run start beyond the minimum headland depth
  double far_v = 0.0;            ///< largest v where the row shows
  double start_v = NAN;          ///< the run start at the edge (NaN: the row's start is not seen there)
  LineFit2D fit;                 ///< refitted on its cells beyond the edge, directed into the rows
};

/// A row at the headland edge, placed across the headland.
struct EdgeRow {
  double u = 0.0;                   ///< where it crosses the edge [m, headland u]
  int line = -1;                    ///< its line in the analysis' lines
  LineFit2D fit;                    ///< its cells beyond the edge
  double start_v = NAN;             ///< NaN: the row's start is not seen at the edge
  double d_min = 0.0, d_max = 0.0;  ///< lateral extent of its cells about u [m]
  bool heading_ok = true;
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  ///< from its faces (its line fit's when too few)
  double direction_sigma = INFINITY;                     ///< standard error of direction's angle [rad]
};

/// Lines perpendicular to the rear wall within [span_lo, span_hi] along it whose runs (stretches looking like
/// a row, nothing wider beside them) start beyond the minimum headland depth, with floor on both sides. Lines
/// reaching back to the rear wall, or with no floor on one side, are walls or partitions, not rows.
std::vector<RowCandidate> findRowCandidates(const thorvald_map::OccupancyGrid& map,
                                            const std::vector<LineSegment>& lines, int rear_wall,
                                            const HeadlandFrame& frame, double span_lo, double span_hi,
                                            const MapAnalyzerParams& params);

/// The headland edge [m, headland v]: the run start most candidates agree on within tolerance_m (ties: the
/// nearest, since occlusion and gaps only make a row seem to start later), refined as the median of the
/// agreeing starts. Sets each candidate's start_v to its start at the edge (left NaN when it has none).
double findHeadlandEdge(std::vector<RowCandidate>* candidates, double tolerance_m);

/// The candidates that go on into the greenhouse beyond the edge (a box edge on the headland does not) and
/// do not start well before it, refitted beyond the edge, sorted along the headland; two lines closer than
/// half a spacing are one row seen twice (its two edges) and the better supported one is kept. A row whose
/// start is not at the edge is named in warnings.
std::vector<EdgeRow> rowsAtEdge(const std::vector<RowCandidate>& candidates, const std::vector<LineSegment>& lines,
                                const HeadlandFrame& frame, double edge_v, const MapAnalyzerParams& params,
                                std::vector<std::string>* warnings);

/// Places each row at the middle between its two faces, measured over its first metres beyond the edge on
/// `input` (the map as given: sparse hits on a face seen at a grazing angle are single cells the speckle
/// removal takes away), and its direction from the faces on `cleaned`. A row seen from one side only gets its
/// other face at the width of the rows seen from both sides (without such a row the cells' mean is used).
/// `wall` is the rear wall's fit. Returns how many rows could be placed by their cells' mean only.
int placeRowsByFaces(const thorvald_map::OccupancyGrid& input, const thorvald_map::OccupancyGrid& cleaned,
                     const HeadlandFrame& frame, const LineFit2D& wall, double edge_v, std::vector<EdgeRow>* rows);

/// The rows' mean direction, each weighted by how well its faces fix it (its line fit's cells when the faces
/// of any row do not).
Eigen::Vector2d meanRowDirection(const std::vector<EdgeRow>& rows);

/// Standard error of a fitted line's direction [rad]: residuals (at least a cell's quantisation) over the
/// spread of its points along it.
double directionSigma(const LineFit2D& fit, double resolution);

}  // namespace greenhouse_rail_nav
