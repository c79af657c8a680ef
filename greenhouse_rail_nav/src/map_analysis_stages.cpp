#include "greenhouse_rail_nav/map_analysis_stages.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "greenhouse_rail_nav/rear_wall.h"

namespace greenhouse_rail_nav {
namespace {

std::string fmt(double value, int decimals = 2) { return formatMetres(value, decimals); }

}  // namespace

std::string joinReasons(const std::vector<std::string>& reasons) {
  std::string out;
  for (const auto& r : reasons) out += (out.empty() ? "" : "; ") + r;
  return out;
}

HeadlandFrame headlandFrameOf(const LineFit2D& wall, double side) {
  HeadlandFrame frame;
  frame.origin = wall.centroid;
  frame.v = side * Eigen::Vector2d(-wall.direction.y(), wall.direction.x());
  frame.u = Eigen::Vector2d(frame.v.y(), -frame.v.x());  // u points right when looking into the rows
  return frame;
}

void takeOuterLinesAsSideWalls(SideScan* left, SideScan* right, std::vector<EdgeRow>* rows) {
  // No floor beyond the outermost line: that line is the side wall itself (seen through a door, it looked
  // like a row). Its inner face bounds the rail sets.
  if (!left->wall_found && left->floor_extent_m < 0.3 && rows->size() >= 2) {
    left->wall_found = true;
    left->wall_u = rows->front().u + rows->front().d_max;
    rows->erase(rows->begin());
  }
  if (!right->wall_found && right->floor_extent_m < 0.3 && rows->size() >= 2) {
    right->wall_found = true;
    right->wall_u = rows->back().u + rows->back().d_min;
    rows->pop_back();
  }
}

EdgeStraightness measureEdgeStraightness(const std::vector<EdgeRow>& rows, double edge_v, double straightness_m,
                                         std::vector<std::string>* warnings) {
  // A row whose start is hidden by something on the headland (or whose first pots are missing) starts
  // later; it is named, not averaged in.
  double sq_start_dev = 0.0;
  EdgeStraightness e;
  for (const auto& r : rows) {
    if (!std::isfinite(r.start_v)) continue;
    const double dev = r.start_v - edge_v;
    if (std::abs(dev) > 2.0 * straightness_m) {
      warnings->push_back("row at " + fmt(r.u) + " m starts " + fmt(dev) + " m off the headland edge");
      continue;
    }
    sq_start_dev += dev * dev;
    ++e.rows_at_edge;
  }
  if (e.rows_at_edge > 0) e.rms_m = std::sqrt(sq_start_dev / e.rows_at_edge);
  return e;
}

int judgeRowHeadings(std::vector<EdgeRow>* rows, const Eigen::Vector2d& rows_mean, double resolution_m,
                     double tolerance_rad) {
  int off = 0;
  for (auto& r : *rows) {
    // A short row's direction is known only to about a cell (and the scatter of its pots) over its length.
    const double allowed = tolerance_rad + (resolution_m + 2.0 * r.fit.rms_residual) / std::max(0.5, r.fit.length());
    r.heading_ok = angleBetweenLines(r.fit.direction, rows_mean) <= allowed;
    off += !r.heading_ok;
  }
  return off;
}

RearWallEnd findRearWallEnd(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, const SideScan& side,
                            double outer_u, double direction, double max_travel_m) {
  RearWallEnd b;
  if (side.wall_found) return b;
  bool floor_beyond = false;
  b.end_u = rearWallEnd(map, frame, outer_u, direction, max_travel_m, &floor_beyond);
  b.distance = direction * (b.end_u - outer_u);
  b.usable = std::isfinite(b.end_u) && floor_beyond && b.distance > 0.0;
  return b;
}

double greenhouseHeading(const std::vector<LineSegment>& lines, int rear_wall, const HeadlandFrame& frame,
                         const std::vector<EdgeRow>& rows, const Eigen::Vector2d& rows_mean, const SideScan& left,
                         const SideScan& right, double edge_v, double perpendicular_tolerance_rad,
                         double resolution_m) {
  const LineFit2D& wall = lines[static_cast<std::size_t>(rear_wall)].fit;
  Eigen::Vector2d axis = frame.v / std::pow(directionSigma(wall, resolution_m), 2);
  for (const auto& r : rows)
    if (std::isfinite(r.direction_sigma)) axis += r.direction / (r.direction_sigma * r.direction_sigma);
  for (const auto& [found, wall_u] :
       {std::make_pair(left.wall_found, left.wall_u), std::make_pair(right.wall_found, right.wall_u)}) {
    if (!found) continue;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const LineFit2D& f = lines[i].fit;
      if (static_cast<int>(i) == rear_wall || angleBetweenLines(f.direction, rows_mean) > perpendicular_tolerance_rad)
        continue;
      const Eigen::Vector2d c = frame.toLocal(f.centroid);
      const double dv = f.direction.dot(frame.v);
      const double u_at_edge = c.x() + f.direction.dot(frame.u) / dv * (edge_v - c.y());
      if (std::abs(u_at_edge - wall_u) > 0.3) continue;
      const double sigma = directionSigma(f, resolution_m);
      axis += (dv > 0 ? 1.0 : -1.0) * f.direction / (sigma * sigma);
    }
  }
  return std::atan2(axis.y(), axis.x());
}

SpacingFit fitSpacing(const SideScan& left, const std::vector<EdgeRow>& rows, const SideScan& right,
                      const MapAnalyzerParams& params, double resolution_m) {
  SpacingFit fit;
  if (left.wall_found) fit.bounds.push_back({left.wall_u, "left side wall", true});
  for (const auto& r : rows) fit.bounds.push_back({r.u, "row at " + fmt(r.u) + " m", r.heading_ok});
  if (right.wall_found) fit.bounds.push_back({right.wall_u, "right side wall", true});
  for (std::size_t k = 0; k + 1 < fit.bounds.size(); ++k) fit.gaps.push_back(fit.bounds[k + 1].u - fit.bounds[k].u);
  fit.fit_tolerance_m = std::max(params.spacing_fit_tolerance_m, 1.5 * resolution_m);
  fit.estimate = estimateSpacing(fit.gaps, params.rail_set_spacing_m, params.spacing_search_ratio, fit.fit_tolerance_m);
  fit.spacing_m = fit.gaps.empty() ? params.rail_set_spacing_m : fit.estimate.spacing_m;
  return fit;
}

GlobalChecks checkLayout(double wall_length_m, const std::vector<EdgeRow>& rows, const EdgeStraightness& edge,
                         double rows_vs_wall_rad, int rows_off_heading, const SpacingFit& fit,
                         const MapAnalyzerParams& params, double resolution_m, std::vector<AnalysisCheck>* checks) {
  auto check = [&](const std::string& name, bool passed, double value, double limit, const std::string& detail) {
    checks->push_back({name, passed, value, limit, detail});
    return passed;
  };
  GlobalChecks g;
  const double row_span = rows.back().u - rows.front().u;
  const int n_rows = static_cast<int>(rows.size());
  g.wall = check("rear_wall_spans_rows", wall_length_m >= 0.8 * row_span, wall_length_m, 0.8 * row_span,
                 "rear wall length [m] against 0.8 of the rows' span");
  g.edge = check("edge_straight",
                 edge.rows_at_edge >= std::min<int>(2, n_rows) && 2 * edge.rows_at_edge >= n_rows &&
                     edge.rms_m <= params.edge_straightness_m,
                 edge.rms_m, params.edge_straightness_m,
                 "RMS of the row starts about the edge [m]; " + std::to_string(edge.rows_at_edge) + " of " +
                     std::to_string(rows.size()) + " rows start at it");
  g.heading = check("rows_agree_in_heading",
                    rows_vs_wall_rad <= params.row_heading_tolerance_rad + 2.0 * resolution_m / wall_length_m,
                    rows_vs_wall_rad, params.row_heading_tolerance_rad,
                    "angle between the rows' mean direction and the rear wall's normal [rad]");
  check("each_row_parallel", rows_off_heading == 0, rows_off_heading, 0,
        "rows whose own direction disagrees with the others' (the sets beside them are uncertain)");
  double worst_residual = 0.0;
  for (const double r : fit.estimate.residual_m) worst_residual = std::max(worst_residual, r);
  g.spacing_regular = check("spacing_regular", fit.estimate.regular, worst_residual, fit.fit_tolerance_m,
                            "largest misfit of a gap to a whole number of spacings [m]");
  g.spacing_unique = check("spacing_unambiguous", fit.estimate.hypotheses <= 1, fit.estimate.hypotheses, 1,
                           "patterns of rail sets per gap that fit every gap within the spacing search range");
  const double s = fit.spacing_m, configured = params.rail_set_spacing_m;
  g.spacing_confirmed =
      check("spacing_confirmed", fit.gaps.size() >= 2 || std::abs(s - configured) <= 0.05 * configured, s, configured,
            "spacing measured from " + std::to_string(fit.gaps.size()) +
                " gaps [m] against the configured one (one gap alone must agree within 5 %)");
  return g;
}

int setsToRearWallEnd(const RearWallEnd& end, const SpacingFit& fit, bool spacing_confirmed, double max_thickness_m) {
  const SpacingEstimate& e = fit.estimate;
  if (!end.usable || fit.gaps.empty() || !e.regular || e.hypotheses > 1 || !spacing_confirmed) return -1;
  const double s = fit.spacing_m;
  const int n = static_cast<int>(std::floor((end.distance + fit.fit_tolerance_m) / s));
  const double remainder = end.distance - n * s;
  return n >= 1 && remainder <= max_thickness_m ? n : -1;
}

SideBounds boundSides(const SideScan& left, const SideScan& right, const RearWallEnd& left_end,
                      const RearWallEnd& right_end, const SpacingFit& fit, bool spacing_confirmed,
                      double max_thickness_m, MapAnalysis* result) {
  SideBounds b;
  b.left_end_sets = setsToRearWallEnd(left_end, fit, spacing_confirmed, max_thickness_m);
  b.right_end_sets = setsToRearWallEnd(right_end, fit, spacing_confirmed, max_thickness_m);
  result->left_by_rear_wall_end = b.left_end_sets >= 0;
  result->right_by_rear_wall_end = b.right_end_sets >= 0;
  auto bound_name = [](bool wall, int end_sets) { return wall ? "wall" : end_sets >= 0 ? "rear wall's end" : "open"; };
  const int sides_bounded = (left.wall_found || b.left_end_sets >= 0) + (right.wall_found || b.right_end_sets >= 0);
  result->checks.push_back(
      {"sides_bounded", sides_bounded == 2, static_cast<double>(sides_bounded), 2,
       std::string("sides bounded by a side wall found by scanlines across the headland, or by the rear wall's "
                   "end a whole number of spacings beyond the outermost row (left: ") +
           bound_name(left.wall_found, b.left_end_sets) + ", right: " + bound_name(right.wall_found, b.right_end_sets) +
           ")"});
  for (const auto& [sets, name, end] : {std::make_tuple(b.left_end_sets, "left", left_end.end_u),
                                        std::make_tuple(b.right_end_sets, "right", right_end.end_u)}) {
    if (sets >= 0)
      result->warnings.push_back(std::string("no ") + name + " side wall found: the rear wall's end at " + fmt(end) +
                                 " m bounds the rail sets, " + std::to_string(sets) +
                                 " placed beyond the outermost row by the spacing");
  }
  return b;
}

int placeRailSets(const std::vector<RailSetPlan>& plans, const HeadlandFrame& frame, double edge_v, double heading,
                  const thorvald_base::Pose2D& target_in_rail, const std::vector<std::string>& global_reasons,
                  MapAnalysis* result) {
  int good = 0;
  for (const auto& plan : plans) {
    RailSetEstimate set;
    set.index = static_cast<int>(result->rail_sets.size());
    const Eigen::Vector2d origin = frame.toMap(plan.u, edge_v);
    set.rail_frame = thorvald_base::Pose2D(origin.x(), origin.y(), heading);
    set.target_pose = set.rail_frame * target_in_rail;
    std::vector<std::string> reasons = global_reasons;
    reasons.insert(reasons.end(), plan.reasons.begin(), plan.reasons.end());
    set.good = reasons.empty();
    set.reason = joinReasons(reasons);
    good += set.good;
    result->rail_sets.push_back(set);
  }
  return good;
}

void judgeAnalysis(int good, int rows_off_heading, const std::vector<std::string>& global_reasons,
                   const SpacingFit& fit, MapAnalysis* result) {
  result->ok = !result->rail_sets.empty();
  int passed = 0;
  std::vector<std::string> failed;
  for (const auto& c : result->checks) {
    passed += c.passed;
    if (!c.passed) failed.push_back(c.name);
  }
  const std::size_t n_sets = result->rail_sets.size();
  result->confidence =
      n_sets == 0 ? 0.0 : static_cast<double>(passed) / result->checks.size() * static_cast<double>(good) / n_sets;
  result->status = !result->ok
                       ? MapStatus::kFailed
                       : (failed.empty() && good == static_cast<int>(n_sets) ? MapStatus::kOk : MapStatus::kUncertain);
  std::vector<std::string> uncertain = global_reasons;
  if (rows_off_heading > 0)
    uncertain.push_back(std::to_string(rows_off_heading) + " rows disagree in heading with the others");
  if (result->left_open) uncertain.push_back("no left side wall found: rail sets may go on beyond the leftmost row");
  if (result->right_open) uncertain.push_back("no right side wall found: rail sets may go on beyond the rightmost row");
  const SpacingEstimate& e = fit.estimate;
  if (!e.regular || e.hypotheses > 1) {
    for (std::size_t k = 0; k < fit.gaps.size(); ++k) {
      if (!e.gap_fits[k] || e.gap_ambiguous[k])
        uncertain.push_back("gap of " + fmt(fit.gaps[k]) + " m between " + fit.bounds[k].name + " and " +
                            fit.bounds[k + 1].name +
                            (e.gap_fits[k] ? " fits more than one number of rail sets" : " does not fit the spacing"));
    }
  }
  if (result->status == MapStatus::kUncertain) {
    result->uncertain_reasons = joinReasons(uncertain);
    if (result->uncertain_reasons.empty()) result->uncertain_reasons = "failed checks: " + joinReasons(failed);
  }
}

}  // namespace greenhouse_rail_nav
