#include "greenhouse_rail_nav/map_analyzer.h"

#include <algorithm>
#include <cmath>

#include "greenhouse_rail_nav/cell_clustering.h"
#include "greenhouse_rail_nav/headland_rows.h"
#include "greenhouse_rail_nav/map_analysis_stages.h"
#include "greenhouse_rail_nav/map_denoise.h"
#include "greenhouse_rail_nav/rear_wall.h"

namespace greenhouse_rail_nav {
namespace {

std::string fmt(double value, int decimals = 2) { return formatMetres(value, decimals); }

// What analyzeMap has found up to the rows at the headland edge.
struct HeadlandRows {
  const thorvald_map::OccupancyGrid& input;  ///< before speckle removal
  const thorvald_map::OccupancyGrid& map;    ///< after it
  HeadlandFrame frame;
  double edge_v = 0.0;
  double span_lo = 0.0, span_hi = 0.0;  ///< the rear wall's extent along u, a metre more each side [m]
  std::string found, wall_text;         ///< the message's beginning
};

// The headland edge's ends and the side walls' places on it, and which sides are open.
void placeHeadlandEdge(const HeadlandRows& h, const SideScan& left, const SideScan& right,
                       const std::vector<EdgeRow>& rows, const std::vector<RailSetPlan>& plans, const SpacingFit& fit,
                       const SideBounds& sides, MapAnalysis* result) {
  const double s = fit.spacing_m;
  const double edge_u0 =
      plans.empty() ? fit.bounds.front().u : std::min(fit.bounds.front().u, plans.front().u - 0.5 * s);
  const double edge_u1 = plans.empty() ? fit.bounds.back().u : std::max(fit.bounds.back().u, plans.back().u + 0.5 * s);
  result->edge_start = h.frame.toMap(left.wall_found ? left.wall_u : edge_u0, h.edge_v);
  result->edge_end = h.frame.toMap(right.wall_found ? right.wall_u : edge_u1, h.edge_v);
  result->left_wall = h.frame.toMap(left.wall_u, h.edge_v);
  result->right_wall = h.frame.toMap(right.wall_u, h.edge_v);
  result->left_open = !left.wall_found && sides.left_end_sets < 0;
  result->right_open = !right.wall_found && sides.right_end_sets < 0;
  if (sides.left_end_sets >= 0) result->left_wall = h.frame.toMap(rows.front().u - sides.left_end_sets * s, h.edge_v);
  if (sides.right_end_sets >= 0) result->right_wall = h.frame.toMap(rows.back().u + sides.right_end_sets * s, h.edge_v);
}

// Everything after the rows: their places and headings, side walls, heading, spacing, checks, rail sets and
// the report.
void analyzeRows(const HeadlandRows& h, std::vector<EdgeRow> rows, const MapAnalyzerParams& params,
                 MapAnalysis* result) {
  const thorvald_map::OccupancyGrid& map = h.map;
  const LineFit2D& wall = result->lines[static_cast<std::size_t>(result->rear_wall)].fit;
  // Each row's place at the edge: the middle between its two faces.
  const int rows_one_face = placeRowsByFaces(h.input, map, h.frame, wall, h.edge_v, &rows);
  if (rows_one_face > 0)
    result->warnings.push_back(std::to_string(rows_one_face) +
                               " rows seen from one side only and no row seen from both: their places may be off by "
                               "half a row's width");
  // Heading: the rows' directions and the rear wall's normal measure the same axis.
  const Eigen::Vector2d rows_mean = meanRowDirection(rows);
  const int rows_off_heading = judgeRowHeadings(&rows, rows_mean, map.resolution_m, params.row_heading_tolerance_rad);
  const double rows_vs_wall = angleBetweenLines(rows_mean, h.frame.v);
  // Side walls by scanlines from the outer rows outwards.
  const double max_travel = (h.span_hi - h.span_lo) + 2.0;
  SideScan left =
      scanToSideWall(map, h.frame, rows.front().u - 0.25, h.edge_v, -1.0, params.side_wall_min_support, max_travel);
  SideScan right =
      scanToSideWall(map, h.frame, rows.back().u + 0.25, h.edge_v, +1.0, params.side_wall_min_support, max_travel);
  takeOuterLinesAsSideWalls(&left, &right, &rows);
  result->rows.clear();
  for (const auto& r : rows) result->rows.push_back(r.line);
  const EdgeStraightness edge = measureEdgeStraightness(rows, h.edge_v, params.edge_straightness_m, &result->warnings);
  result->left_wall_found = left.wall_found;
  result->right_wall_found = right.wall_found;
  const RearWallEnd left_end = findRearWallEnd(map, h.frame, left, rows.front().u, -1.0, max_travel);
  const RearWallEnd right_end = findRearWallEnd(map, h.frame, right, rows.back().u, +1.0, max_travel);
  const double heading = greenhouseHeading(result->lines, result->rear_wall, h.frame, rows, rows_mean, left, right,
                                           h.edge_v, params.perpendicular_tolerance_rad, map.resolution_m);
  // Lines across the headland (walls, rows), the gaps between them and the checks behind the whole result.
  const SpacingFit fit = fitSpacing(left, rows, right, params, map.resolution_m);
  result->spacing_m = fit.gaps.empty() ? 0.0 : fit.estimate.spacing_m;
  const double s = fit.spacing_m;
  const GlobalChecks ok = checkLayout(wall.length(), rows, edge, rows_vs_wall, rows_off_heading, fit, params,
                                      map.resolution_m, &result->checks);
  const SideBounds sides =
      boundSides(left, right, left_end, right_end, fit, ok.spacing_confirmed, params.side_wall_max_thickness_m, result);
  if (!fit.gaps.empty() &&
      std::abs(s - params.rail_set_spacing_m) > params.spacing_tolerance * params.rail_set_spacing_m)
    result->warnings.push_back("measured rail-set spacing " + formatMetres(s) + " m differs from the configured " +
                               formatMetres(params.rail_set_spacing_m) + " m; the measured one is used");
  std::vector<std::string> global_reasons;
  if (!ok.wall) global_reasons.push_back("rear wall shorter than the span of the rows");
  if (!ok.edge) global_reasons.push_back("headland edge not confirmed by the row starts");
  if (!ok.heading) global_reasons.push_back("rows disagree in heading with the rear wall");
  if (!ok.spacing_confirmed) global_reasons.push_back("spacing measured from one gap only and not the configured one");
  // Rail sets: whole numbers of spacings in each gap; on a side without a wall, sets by the spacing as
  // far as the mapped floor goes, all uncertain.
  const std::vector<RailSetPlan> plans = planRailSets(fit.bounds, fit.estimate, s, left, right, rows.front().u,
                                                      rows.back().u, sides.left_end_sets, sides.right_end_sets);
  if (!ok.spacing_regular && ok.spacing_unique) global_reasons.push_back("rows and walls are not a regular pattern");
  placeHeadlandEdge(h, left, right, rows, plans, fit, sides, result);
  const int good = placeRailSets(plans, h.frame, h.edge_v, heading, params.target_in_rail, global_reasons, result);
  judgeAnalysis(good, rows_off_heading, global_reasons, fit, result);
  result->message = h.found + ": " + h.wall_text + ", " + std::to_string(rows.size()) +
                    " rows/ventilation lines, headland edge " + formatMetres(h.edge_v) +
                    " m from the rear wall, side walls " + (left.wall_found ? "left " : "") +
                    (right.wall_found ? "right " : "") + (left.wall_found || right.wall_found ? "found" : "not found") +
                    ", spacing " + formatMetres(s) + " m, " + std::to_string(result->rail_sets.size()) +
                    " rail sets (" + std::to_string(good) + " good)";
  if (!result->ok) result->message += "; expected at least two lines (rows or walls) a rail-set spacing apart";
}

}  // namespace

const char* toString(MapStatus status) {
  switch (status) {
    case MapStatus::kOk:
      return "ok";
    case MapStatus::kUncertain:
      return "uncertain";
    case MapStatus::kFailed:
      break;
  }
  return "failed";
}

std::string MapAnalyzerParams::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(rail_set_spacing_m)) return "rail_set_spacing_m must be > 0 [m]";
  if (!positive(rail_gauge_m) || rail_gauge_m >= rail_set_spacing_m)
    return "rail_gauge_m must be > 0 and < rail_set_spacing_m [m]";
  if (!std::isfinite(target_in_rail.x) || !std::isfinite(target_in_rail.y) || !std::isfinite(target_in_rail.yaw))
    return "target_in_rail must be finite numbers [x m, y m, yaw rad]";
  if (!positive(cluster_link_radius_m)) return "cluster_link_radius_m must be > 0 [m]";
  if (min_cluster_cells < 2) return "min_cluster_cells must be >= 2";
  if (!(lines.min_linearity > 0.0 && lines.min_linearity < 1.0)) return "min_linearity must be in (0, 1)";
  if (!positive(lines.min_length_m)) return "min_line_length_m must be > 0 [m]";
  if (!positive(lines.split_inlier_m)) return "split_inlier_m must be > 0 [m]";
  if (!positive(lines.max_gap_m)) return "max_gap_m must be > 0 [m]";
  if (!positive(lines.merge_angle_rad)) return "merge_angle_rad must be > 0 [rad]";
  if (!positive(lines.merge_offset_m)) return "merge_offset_m must be > 0 [m]";
  if (!(perpendicular_tolerance_rad > 0.0 && perpendicular_tolerance_rad < M_PI / 4))
    return "perpendicular_tolerance_rad must be in (0, pi/4)";
  if (!(min_headland_depth_m >= 0.0)) return "min_headland_depth_m must be >= 0 [m]";
  if (!positive(edge_tolerance_m)) return "edge_tolerance_m must be > 0 [m]";
  if (!(spacing_tolerance > 0.0 && spacing_tolerance < 0.5)) return "spacing_tolerance must be in (0, 0.5)";
  if (!std::isfinite(keep_out_margin_m)) return "keep_out_margin_m must be a finite number [m]";
  if (!(speckle_max_area_m2 >= 0.0 && speckle_max_area_m2 <= 0.1)) return "speckle_max_area_m2 must be in [0, 0.1]";
  if (!(speckle_link_radius_m >= 0.0 && speckle_link_radius_m <= 0.5))
    return "speckle_link_radius_m must be in [0, 0.5] [m]";
  if (!(spacing_search_ratio >= 1.0 && spacing_search_ratio <= 2.0)) return "spacing_search_ratio must be in [1, 2]";
  if (!(positive(spacing_fit_tolerance_m) && spacing_fit_tolerance_m < 0.25 * rail_set_spacing_m))
    return "spacing_fit_tolerance_m must be > 0 and < a quarter of rail_set_spacing_m [m]";
  if (!(positive(row_heading_tolerance_rad) && row_heading_tolerance_rad < 0.2))
    return "row_heading_tolerance_rad must be in (0, 0.2) [rad]";
  if (!positive(edge_straightness_m)) return "edge_straightness_m must be > 0 [m]";
  if (!(side_wall_min_support > 0.0 && side_wall_min_support <= 1.0)) return "side_wall_min_support must be in (0, 1]";
  if (!(side_wall_max_thickness_m >= 0.0 && side_wall_max_thickness_m < 0.5 * rail_set_spacing_m))
    return "side_wall_max_thickness_m must be >= 0 and < half of rail_set_spacing_m [m]";
  return "";
}

MapAnalysis analyzeMap(const thorvald_map::OccupancyGrid& input, const MapAnalyzerParams& params) {
  MapAnalysis result;
  thorvald_map::OccupancyGrid map = input;
  result.speckle_cells_removed = removeSpeckle(&map, params.speckle_max_area_m2, params.speckle_link_radius_m);
  const auto clusters =
      clusterOccupiedCells(map, params.cluster_link_radius_m, static_cast<std::size_t>(params.min_cluster_cells));
  result.lines = extractLines(clusters, params.lines);
  const auto& lines = result.lines;
  HeadlandRows h{input, map};
  h.found = "removed " + std::to_string(result.speckle_cells_removed) + " speckle cells; found " +
            std::to_string(clusters.size()) + " clusters of >= " + std::to_string(params.min_cluster_cells) +
            " occupied cells and " + std::to_string(lines.size()) + " straight lines";
  if (lines.empty()) {
    result.message = h.found + "; expected a rear wall and at least one row or ventilation line";
    return result;
  }

  double side = 1.0;
  result.rear_wall = selectRearWall(lines, params.perpendicular_tolerance_rad, &side);
  const LineFit2D& wall = lines[static_cast<std::size_t>(result.rear_wall)].fit;
  h.frame = headlandFrameOf(wall, side);
  result.into_rows = h.frame.v;
  h.wall_text = "rear wall of " + fmt(wall.length(), 1) + " m";
  const double wall_u_min = h.frame.toLocal(wall.centroid + wall.direction * wall.s_min).x();
  const double wall_u_max = h.frame.toLocal(wall.centroid + wall.direction * wall.s_max).x();
  h.span_lo = std::min(wall_u_min, wall_u_max) - 1.0;
  h.span_hi = std::max(wall_u_min, wall_u_max) + 1.0;

  // Rows: lines perpendicular to the rear wall within its span whose row-like runs start beyond the minimum
  // headland depth; the headland edge is where most of them start.
  std::vector<RowCandidate> candidates =
      findRowCandidates(map, lines, result.rear_wall, h.frame, h.span_lo, h.span_hi, params);
  if (candidates.empty()) {
    result.message = h.found + " (" + h.wall_text +
                     "), but no row perpendicular to it starting >= " + fmt(params.min_headland_depth_m, 1) +
                     " m from it; expected at least one row or ventilation line perpendicular to the rear wall";
    return result;
  }
  h.edge_v = findHeadlandEdge(&candidates, params.edge_tolerance_m);
  std::vector<EdgeRow> rows = rowsAtEdge(candidates, lines, h.frame, h.edge_v, params, &result.warnings);
  if (rows.empty()) {
    result.message = h.found + " (" + h.wall_text + "), " + std::to_string(candidates.size()) +
                     " lines perpendicular to it, none going on beyond a common headland edge; expected rows "
                     "starting along one headland edge";
    return result;
  }
  for (const auto& r : rows) result.rows.push_back(r.line);
  analyzeRows(h, std::move(rows), params, &result);
  return result;
}

}  // namespace greenhouse_rail_nav
