#include "greenhouse_rail_nav/map_analyzer.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "greenhouse_rail_nav/cell_clustering.h"
#include "greenhouse_rail_nav/headland_rows.h"
#include "greenhouse_rail_nav/headland_scan.h"
#include "greenhouse_rail_nav/map_denoise.h"
#include "greenhouse_rail_nav/rail_set_layout.h"
#include "greenhouse_rail_nav/rail_spacing.h"
#include "greenhouse_rail_nav/rear_wall.h"

namespace greenhouse_rail_nav {
namespace {

std::string fmt(double value, int decimals = 2) { return formatMetres(value, decimals); }

std::string joinReasons(const std::vector<std::string>& reasons) {
  std::string out;
  for (const auto& r : reasons) out += (out.empty() ? "" : "; ") + r;
  return out;
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
  const std::string found = "removed " + std::to_string(result.speckle_cells_removed) + " speckle cells; found " +
                            std::to_string(clusters.size()) +
                            " clusters of >= " + std::to_string(params.min_cluster_cells) + " occupied cells and " +
                            std::to_string(lines.size()) + " straight lines";
  if (lines.empty()) {
    result.message = found + "; expected a rear wall and at least one row or ventilation line";
    return result;
  }

  double side = 1.0;
  result.rear_wall = selectRearWall(lines, params.perpendicular_tolerance_rad, &side);
  const LineFit2D& wall = lines[static_cast<std::size_t>(result.rear_wall)].fit;
  HeadlandFrame frame;
  frame.origin = wall.centroid;
  frame.v = side * Eigen::Vector2d(-wall.direction.y(), wall.direction.x());
  frame.u = Eigen::Vector2d(frame.v.y(), -frame.v.x());  // u points right when looking into the rows
  result.into_rows = frame.v;
  const std::string wall_text = "rear wall of " + fmt(wall.length(), 1) + " m";
  const double wall_u_min = frame.toLocal(wall.centroid + wall.direction * wall.s_min).x();
  const double wall_u_max = frame.toLocal(wall.centroid + wall.direction * wall.s_max).x();
  const double span_lo = std::min(wall_u_min, wall_u_max) - 1.0, span_hi = std::max(wall_u_min, wall_u_max) + 1.0;

  // Rows: lines perpendicular to the rear wall within its span whose row-like runs start beyond the minimum
  // headland depth; the headland edge is where most of them start.
  std::vector<RowCandidate> candidates =
      findRowCandidates(map, lines, result.rear_wall, frame, span_lo, span_hi, params);
  if (candidates.empty()) {
    result.message = found + " (" + wall_text +
                     "), but no row perpendicular to it starting >= " + fmt(params.min_headland_depth_m, 1) +
                     " m from it; expected at least one row or ventilation line perpendicular to the rear wall";
    return result;
  }
  const double edge_v = findHeadlandEdge(&candidates, params.edge_tolerance_m);
  std::vector<EdgeRow> rows = rowsAtEdge(candidates, lines, frame, edge_v, params, &result.warnings);
  if (rows.empty()) {
    result.message = found + " (" + wall_text + "), " + std::to_string(candidates.size()) +
                     " lines perpendicular to it, none going on beyond a common headland edge; expected rows "
                     "starting along one headland edge";
    return result;
  }
  for (const auto& r : rows) result.rows.push_back(r.line);

  // Each row's place at the edge: the middle between its two faces.
  const int rows_one_face = placeRowsByFaces(input, map, frame, wall, edge_v, &rows);
  if (rows_one_face > 0)
    result.warnings.push_back(std::to_string(rows_one_face) +
                              " rows seen from one side only and no row seen from both: their places may be off by "
                              "half a row's width");

  // Heading: the rows' directions and the rear wall's normal measure the same axis.
  const Eigen::Vector2d rows_mean = meanRowDirection(rows);
  int rows_off_heading = 0;
  for (auto& r : rows) {
    // A short row's direction is known only to about a cell (and the scatter of its pots) over its length.
    const double allowed = params.row_heading_tolerance_rad +
                           (map.resolution_m + 2.0 * r.fit.rms_residual) / std::max(0.5, r.fit.length());
    r.heading_ok = angleBetweenLines(r.fit.direction, rows_mean) <= allowed;
    rows_off_heading += !r.heading_ok;
  }
  const double rows_vs_wall = angleBetweenLines(rows_mean, frame.v);

  // Side walls by scanlines from the outer rows outwards.
  const double max_travel = (span_hi - span_lo) + 2.0;
  SideScan left =
      scanToSideWall(map, frame, rows.front().u - 0.25, edge_v, -1.0, params.side_wall_min_support, max_travel);
  SideScan right =
      scanToSideWall(map, frame, rows.back().u + 0.25, edge_v, +1.0, params.side_wall_min_support, max_travel);
  // No floor beyond the outermost line: that line is the side wall itself (seen through a door, it looked
  // like a row). Its inner face bounds the rail sets.
  if (!left.wall_found && left.floor_extent_m < 0.3 && rows.size() >= 2) {
    left.wall_found = true;
    left.wall_u = rows.front().u + rows.front().d_max;
    rows.erase(rows.begin());
  }
  if (!right.wall_found && right.floor_extent_m < 0.3 && rows.size() >= 2) {
    right.wall_found = true;
    right.wall_u = rows.back().u + rows.back().d_min;
    rows.pop_back();
  }
  result.rows.clear();
  for (const auto& r : rows) result.rows.push_back(r.line);
  // Straightness of the edge from the row starts that lie on it: a row whose start is hidden by something
  // on the headland (or whose first pots are missing) starts later; it is named, not averaged in.
  double sq_start_dev = 0.0;
  int with_start = 0;
  for (const auto& r : rows) {
    if (!std::isfinite(r.start_v)) continue;
    const double dev = r.start_v - edge_v;
    if (std::abs(dev) > 2.0 * params.edge_straightness_m) {
      result.warnings.push_back("row at " + fmt(r.u) + " m starts " + fmt(dev) + " m off the headland edge");
      continue;
    }
    sq_start_dev += dev * dev;
    ++with_start;
  }
  result.left_wall_found = left.wall_found;
  result.right_wall_found = right.wall_found;
  // No side wall, but the rear wall ends with floor beyond it: the greenhouse's corner, behind the unseen
  // side wall's inner face by that wall's thickness. It bounds the sets beyond the outermost row when it
  // lies a whole number of the rows' spacings from that row plus at most a wall's thickness; those sets
  // are placed by the rows' pattern. The spacing comes from the gaps measured below.
  struct EndBound {
    bool usable = false;
    double end_u = NAN, distance = 0.0;
  };
  auto end_bound = [&](bool wall_found, double outer_u, double direction) {
    EndBound b;
    if (wall_found) return b;
    bool floor_beyond = false;
    b.end_u = rearWallEnd(map, frame, outer_u, direction, max_travel, &floor_beyond);
    b.distance = direction * (b.end_u - outer_u);
    b.usable = std::isfinite(b.end_u) && floor_beyond && b.distance > 0.0;
    return b;
  };
  const EndBound left_end = end_bound(left.wall_found, rows.front().u, -1.0);
  const EndBound right_end = end_bound(right.wall_found, rows.back().u, +1.0);
  // The greenhouse's heading: every straight piece along its axis, each weighted by how well it fixes a
  // direction (inverse variance): the rear wall's normal, the rows' faces and the side walls, which are
  // the longest lines of a headland map.
  Eigen::Vector2d axis = frame.v / std::pow(directionSigma(wall, map.resolution_m), 2);
  for (const auto& r : rows)
    if (std::isfinite(r.direction_sigma)) axis += r.direction / (r.direction_sigma * r.direction_sigma);
  for (const auto& [found, wall_u] :
       {std::make_pair(left.wall_found, left.wall_u), std::make_pair(right.wall_found, right.wall_u)}) {
    if (!found) continue;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const LineFit2D& f = lines[i].fit;
      if (static_cast<int>(i) == result.rear_wall ||
          angleBetweenLines(f.direction, rows_mean) > params.perpendicular_tolerance_rad)
        continue;
      const Eigen::Vector2d c = frame.toLocal(f.centroid);
      const double dv = f.direction.dot(frame.v);
      const double u_at_edge = c.x() + f.direction.dot(frame.u) / dv * (edge_v - c.y());
      if (std::abs(u_at_edge - wall_u) > 0.3) continue;
      const double sigma = directionSigma(f, map.resolution_m);
      axis += (dv > 0 ? 1.0 : -1.0) * f.direction / (sigma * sigma);
    }
  }
  const double heading = std::atan2(axis.y(), axis.x());

  // Lines across the headland (walls, rows) and the gaps between them.
  std::vector<HeadlandBoundary> bounds;
  if (left.wall_found) bounds.push_back({left.wall_u, "left side wall", true});
  for (const auto& r : rows) bounds.push_back({r.u, "row at " + fmt(r.u) + " m", r.heading_ok});
  if (right.wall_found) bounds.push_back({right.wall_u, "right side wall", true});
  std::vector<double> gaps;
  for (std::size_t k = 0; k + 1 < bounds.size(); ++k) gaps.push_back(bounds[k + 1].u - bounds[k].u);
  const double fit_tol = std::max(params.spacing_fit_tolerance_m, 1.5 * map.resolution_m);
  const SpacingEstimate spacing =
      estimateSpacing(gaps, params.rail_set_spacing_m, params.spacing_search_ratio, fit_tol);
  result.spacing_m = gaps.empty() ? 0.0 : spacing.spacing_m;
  const double s = gaps.empty() ? params.rail_set_spacing_m : spacing.spacing_m;

  // Checks behind the whole result.
  auto check = [&](const std::string& name, bool passed, double value, double limit, const std::string& detail) {
    result.checks.push_back({name, passed, value, limit, detail});
    return passed;
  };
  const double row_span = rows.back().u - rows.front().u;
  const bool wall_ok = check("rear_wall_spans_rows", wall.length() >= 0.8 * row_span, wall.length(), 0.8 * row_span,
                             "rear wall length [m] against 0.8 of the rows' span");
  const double edge_rms = with_start ? std::sqrt(sq_start_dev / with_start) : INFINITY;
  const bool edge_ok =
      check("edge_straight",
            with_start >= std::min<int>(2, static_cast<int>(rows.size())) &&
                2 * with_start >= static_cast<int>(rows.size()) && edge_rms <= params.edge_straightness_m,
            edge_rms, params.edge_straightness_m,
            "RMS of the row starts about the edge [m]; " + std::to_string(with_start) + " of " +
                std::to_string(rows.size()) + " rows start at it");
  const bool heading_ok = check(
      "rows_agree_in_heading",
      rows_vs_wall <= params.row_heading_tolerance_rad + 2.0 * map.resolution_m / wall.length(), rows_vs_wall,
      params.row_heading_tolerance_rad, "angle between the rows' mean direction and the rear wall's normal [rad]");
  check("each_row_parallel", rows_off_heading == 0, rows_off_heading, 0,
        "rows whose own direction disagrees with the others' (the sets beside them are uncertain)");
  double worst_residual = 0.0;
  for (const double r : spacing.residual_m) worst_residual = std::max(worst_residual, r);
  const bool spacing_regular = check("spacing_regular", spacing.regular, worst_residual, fit_tol,
                                     "largest misfit of a gap to a whole number of spacings [m]");
  const bool spacing_unique = check("spacing_unambiguous", spacing.hypotheses <= 1, spacing.hypotheses, 1,
                                    "patterns of rail sets per gap that fit every gap within the spacing search range");
  const bool spacing_confirmed =
      check("spacing_confirmed",
            gaps.size() >= 2 || std::abs(s - params.rail_set_spacing_m) <= 0.05 * params.rail_set_spacing_m, s,
            params.rail_set_spacing_m,
            "spacing measured from " + std::to_string(gaps.size()) +
                " gaps [m] against the configured one (one gap alone must agree within 5 %)");
  // Sets between the outermost row and a rear wall's end: a whole number of spacings, the remainder the
  // corner's wall (at most side_wall_max_thickness_m), on a regular pattern measured from at least one gap.
  auto sets_to_end = [&](const EndBound& b) {
    if (!b.usable || gaps.empty() || !spacing.regular || spacing.hypotheses > 1 || !spacing_confirmed) return -1;
    const int n = static_cast<int>(std::floor((b.distance + fit_tol) / s));
    const double remainder = b.distance - n * s;
    return n >= 1 && remainder <= params.side_wall_max_thickness_m ? n : -1;
  };
  const int left_end_sets = sets_to_end(left_end), right_end_sets = sets_to_end(right_end);
  result.left_by_rear_wall_end = left_end_sets >= 0;
  result.right_by_rear_wall_end = right_end_sets >= 0;
  const int sides_bounded = (left.wall_found || left_end_sets >= 0) + (right.wall_found || right_end_sets >= 0);
  check("sides_bounded", sides_bounded == 2, sides_bounded, 2,
        std::string("sides bounded by a side wall found by scanlines across the headland, or by the rear wall's "
                    "end a whole number of spacings beyond the outermost row (left: ") +
            (left.wall_found      ? "wall"
             : left_end_sets >= 0 ? "rear wall's end"
                                  : "open") +
            ", right: " +
            (right.wall_found      ? "wall"
             : right_end_sets >= 0 ? "rear wall's end"
                                   : "open") +
            ")");
  for (const auto& [sets, name, end] : {std::make_tuple(left_end_sets, "left", left_end.end_u),
                                        std::make_tuple(right_end_sets, "right", right_end.end_u)}) {
    if (sets >= 0)
      result.warnings.push_back(std::string("no ") + name + " side wall found: the rear wall's end at " + fmt(end) +
                                " m bounds the rail sets, " + std::to_string(sets) +
                                " placed beyond the outermost row by the spacing");
  }
  if (!gaps.empty() && std::abs(s - params.rail_set_spacing_m) > params.spacing_tolerance * params.rail_set_spacing_m)
    result.warnings.push_back("measured rail-set spacing " + fmt(s) + " m differs from the configured " +
                              fmt(params.rail_set_spacing_m) + " m; the measured one is used");
  std::vector<std::string> global_reasons;
  if (!wall_ok) global_reasons.push_back("rear wall shorter than the span of the rows");
  if (!edge_ok) global_reasons.push_back("headland edge not confirmed by the row starts");
  if (!heading_ok) global_reasons.push_back("rows disagree in heading with the rear wall");
  if (!spacing_confirmed) global_reasons.push_back("spacing measured from one gap only and not the configured one");

  // Rail sets: whole numbers of spacings in each gap; on a side without a wall, sets by the spacing as
  // far as the mapped floor goes, all uncertain.
  const std::vector<RailSetPlan> plans =
      planRailSets(bounds, spacing, s, left, right, rows.front().u, rows.back().u, left_end_sets, right_end_sets);
  if (!spacing_regular && spacing_unique) global_reasons.push_back("rows and walls are not a regular pattern");
  const double edge_u0 = plans.empty() ? bounds.front().u : std::min(bounds.front().u, plans.front().u - 0.5 * s);
  const double edge_u1 = plans.empty() ? bounds.back().u : std::max(bounds.back().u, plans.back().u + 0.5 * s);
  result.edge_start = frame.toMap(left.wall_found ? left.wall_u : edge_u0, edge_v);
  result.edge_end = frame.toMap(right.wall_found ? right.wall_u : edge_u1, edge_v);
  result.left_wall = frame.toMap(left.wall_u, edge_v);
  result.right_wall = frame.toMap(right.wall_u, edge_v);
  result.left_open = !left.wall_found && left_end_sets < 0;
  result.right_open = !right.wall_found && right_end_sets < 0;
  if (left_end_sets >= 0) result.left_wall = frame.toMap(rows.front().u - left_end_sets * s, edge_v);
  if (right_end_sets >= 0) result.right_wall = frame.toMap(rows.back().u + right_end_sets * s, edge_v);
  int good = 0;
  for (const auto& plan : plans) {
    RailSetEstimate set;
    set.index = static_cast<int>(result.rail_sets.size());
    const Eigen::Vector2d origin = frame.toMap(plan.u, edge_v);
    set.rail_frame = thorvald_base::Pose2D(origin.x(), origin.y(), heading);
    set.target_pose = set.rail_frame * params.target_in_rail;
    std::vector<std::string> reasons = global_reasons;
    reasons.insert(reasons.end(), plan.reasons.begin(), plan.reasons.end());
    set.good = reasons.empty();
    set.reason = joinReasons(reasons);
    good += set.good;
    result.rail_sets.push_back(set);
  }

  result.ok = !result.rail_sets.empty();
  int passed = 0;
  std::vector<std::string> failed;
  for (const auto& c : result.checks) {
    passed += c.passed;
    if (!c.passed) failed.push_back(c.name);
  }
  result.confidence = result.rail_sets.empty() ? 0.0
                                               : static_cast<double>(passed) / result.checks.size() *
                                                     static_cast<double>(good) / result.rail_sets.size();
  result.status = !result.ok
                      ? MapStatus::kFailed
                      : (failed.empty() && good == static_cast<int>(result.rail_sets.size()) ? MapStatus::kOk
                                                                                             : MapStatus::kUncertain);
  std::vector<std::string> uncertain = global_reasons;
  if (rows_off_heading > 0)
    uncertain.push_back(std::to_string(rows_off_heading) + " rows disagree in heading with the others");
  if (result.left_open) uncertain.push_back("no left side wall found: rail sets may go on beyond the leftmost row");
  if (result.right_open) uncertain.push_back("no right side wall found: rail sets may go on beyond the rightmost row");
  if (!spacing_regular || !spacing_unique) {
    for (std::size_t k = 0; k < gaps.size(); ++k) {
      if (!spacing.gap_fits[k] || spacing.gap_ambiguous[k])
        uncertain.push_back(
            "gap of " + fmt(gaps[k]) + " m between " + bounds[k].name + " and " + bounds[k + 1].name +
            (spacing.gap_fits[k] ? " fits more than one number of rail sets" : " does not fit the spacing"));
    }
  }
  if (result.status == MapStatus::kUncertain) {
    result.uncertain_reasons = joinReasons(uncertain);
    if (result.uncertain_reasons.empty()) result.uncertain_reasons = "failed checks: " + joinReasons(failed);
  }
  result.message = found + ": " + wall_text + ", " + std::to_string(rows.size()) +
                   " rows/ventilation lines, headland edge " + fmt(edge_v) + " m from the rear wall, side walls " +
                   (left.wall_found ? "left " : "") + (right.wall_found ? "right " : "") +
                   (left.wall_found || right.wall_found ? "found" : "not found") + ", spacing " + fmt(s) + " m, " +
                   std::to_string(result.rail_sets.size()) + " rail sets (" + std::to_string(good) + " good)";
  if (!result.ok) result.message += "; expected at least two lines (rows or walls) a rail-set spacing apart";
  return result;
}

}  // namespace greenhouse_rail_nav
