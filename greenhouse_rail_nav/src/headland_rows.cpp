#include "greenhouse_rail_nav/headland_rows.h"

#include <algorithm>
#include <cstdint>

#include "greenhouse_rail_nav/line_fit.h"
#include "greenhouse_rail_nav/rail_set_layout.h"

namespace greenhouse_rail_nav {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Line through the cells of a line segment, optionally only those with v >= v_min, as u = u0 + slope * v.
bool fitRowLine(const LineSegment& segment, const HeadlandFrame& frame, double v_min, double inlier_m, LineFit2D* fit,
                double* u0, double* slope) {
  std::vector<Eigen::Vector2d> points;
  for (const auto& p : segment.points) {
    if (std::abs(segment.fit.signedDistance(p)) <= inlier_m && frame.toLocal(p).y() >= v_min) points.push_back(p);
  }
  if (points.size() < 3) return false;
  *fit = fitLine(points);
  if (fit->direction.dot(frame.v) < 0.0) fit->flip();
  const Eigen::Vector2d c = frame.toLocal(fit->centroid);
  const double dv = fit->direction.dot(frame.v), du = fit->direction.dot(frame.u);
  if (dv < 0.5) return false;
  *slope = du / dv;
  *u0 = c.x() - *slope * c.y();
  return true;
}

/// Whether free floor shows on both sides of a line u = u0 + slope * v over [v_from, v_to]: a row stands
/// on the floor between two paths, while a side wall (or a piece of one behind a door) has the outside of
/// the greenhouse, never mapped as floor, on one side. A side has floor when at least a third of the samples
/// along the line find a free cell between lateral_min_m and lateral_max_m from it.
bool floorOnBothSides(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, double u0, double slope,
                      double v_from, double v_to, double lateral_min_m, double lateral_max_m) {
  int samples = 0, left = 0, right = 0;
  const double step = std::max(map.resolution_m, 0.1);
  for (double v = v_from; v <= v_to; v += step) {
    ++samples;
    const double u_line = u0 + slope * v;
    for (const double side : {-1.0, 1.0}) {
      bool free = false;
      for (double d = lateral_min_m; d <= lateral_max_m && !free; d += map.resolution_m) {
        const std::int8_t value = map.valueAt(frame.toMap(u_line + side * d, v));
        free = value >= 0 && value < 25;
      }
      (side < 0 ? left : right) += free;
    }
  }
  return samples > 0 && 3 * left >= samples && 3 * right >= samples;
}

/// How far a row's cells may lie from its line and still be fitted [m].
double rowInlier(const MapAnalyzerParams& params) { return params.lines.split_inlier_m * 1.5; }

}  // namespace

double directionSigma(const LineFit2D& fit, double resolution) {
  const double sigma = std::max(fit.rms_residual, resolution / std::sqrt(12.0));
  const double n = std::max<double>(2.0, static_cast<double>(fit.count));
  return sigma * std::sqrt(12.0 / n) / std::max(fit.length(), resolution);
}

std::vector<RowCandidate> findRowCandidates(const thorvald_map::OccupancyGrid& map,
                                            const std::vector<LineSegment>& lines, int rear_wall,
                                            const HeadlandFrame& frame, double span_lo, double span_hi,
                                            const MapAnalyzerParams& params) {
  const LineFit2D& wall = lines[static_cast<std::size_t>(rear_wall)].fit;
  std::vector<RowCandidate> candidates;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (static_cast<int>(i) == rear_wall || !perpendicular(wall, lines[i].fit, params.perpendicular_tolerance_rad))
      continue;
    RowCandidate row;
    row.line = static_cast<int>(i);
    if (!fitRowLine(lines[i], frame, -1e9, rowInlier(params), &row.fit, &row.u0, &row.slope)) continue;
    if (row.u0 < span_lo || row.u0 > span_hi) continue;
    double v_lo = 1e9, v_hi = -1e9;
    for (const auto& p : lines[i].points) {
      const double v = frame.toLocal(p).y();
      v_lo = std::min(v_lo, v);
      v_hi = std::max(v_hi, v);
    }
    // A line reaching back to the rear wall is a side wall (or a partition), not a row.
    if (v_lo < 0.5 * params.min_headland_depth_m) continue;
    const auto starts =
        rowRunStarts(map, frame, row.u0, row.slope, std::max(0.0, v_lo - 1.0), v_hi + map.resolution_m, &row.far_v);
    // A line that looks like a row right from the rear wall is a side wall (or a partition), not a row.
    if (starts.empty() || starts.front() < 0.5 * params.min_headland_depth_m) continue;
    for (const double s : starts)
      if (s >= params.min_headland_depth_m) row.starts.push_back(s);
    // A line with no floor on one side is a side wall (seen behind a door, it starts like a row).
    if (!row.starts.empty() &&
        !floorOnBothSides(map, frame, row.u0, row.slope, row.starts.front(),
                          std::min(row.far_v, row.starts.front() + 3.0), 0.25,
                          std::max(0.3, 0.4 * params.rail_set_spacing_m / params.spacing_search_ratio)))
      continue;
    if (!row.starts.empty()) candidates.push_back(row);
  }
  return candidates;
}

double findHeadlandEdge(std::vector<RowCandidate>* candidates, double tolerance_m) {
  double seed_v = 0.0;
  std::size_t best_support = 0;
  for (const auto& c : *candidates) {
    for (const double s : c.starts) {
      std::size_t support = 0;
      for (const auto& other : *candidates)
        support += std::any_of(other.starts.begin(), other.starts.end(),
                               [&](double o) { return std::abs(o - s) <= tolerance_m; });
      if (support > best_support || (support == best_support && s < seed_v)) {
        best_support = support;
        seed_v = s;
      }
    }
  }
  std::vector<double> agreeing;
  for (auto& c : *candidates) {
    for (const double s : c.starts) {
      if (std::abs(s - seed_v) <= tolerance_m) {
        c.start_v = s;
        agreeing.push_back(s);
        break;
      }
    }
  }
  return median(agreeing);
}

std::vector<EdgeRow> rowsAtEdge(const std::vector<RowCandidate>& candidates, const std::vector<LineSegment>& lines,
                                const HeadlandFrame& frame, double edge_v, const MapAnalyzerParams& params,
                                std::vector<std::string>* warnings) {
  std::vector<EdgeRow> rows;
  for (const auto& c : candidates) {
    if (c.far_v < edge_v + 0.5) continue;
    // Something row-like starting well before the edge is a wall or partition (a side wall behind a
    // door), not a row: rows start at the edge or, when occluded, later.
    if (c.starts.front() < edge_v - params.edge_tolerance_m) continue;
    EdgeRow row;
    double u0 = c.u0, slope = c.slope;
    if (!fitRowLine(lines[static_cast<std::size_t>(c.line)], frame, edge_v - 0.05, rowInlier(params), &row.fit, &u0,
                    &slope))
      continue;
    row.u = u0 + slope * edge_v;
    row.line = c.line;
    row.start_v = c.start_v;
    rows.push_back(row);
    if (!std::isfinite(c.start_v))
      warnings->push_back("row at " + formatMetres(row.u) + " m along the rear wall does not start at the edge");
  }
  std::sort(rows.begin(), rows.end(), [](const EdgeRow& a, const EdgeRow& b) { return a.u < b.u; });
  std::vector<EdgeRow> merged;
  for (const auto& r : rows) {
    if (!merged.empty() && r.u - merged.back().u < 0.5 * params.rail_set_spacing_m / params.spacing_search_ratio) {
      if (r.fit.count > merged.back().fit.count) merged.back() = r;
      continue;
    }
    merged.push_back(r);
  }
  return merged;
}

int placeRowsByFaces(const thorvald_map::OccupancyGrid& input, const thorvald_map::OccupancyGrid& cleaned,
                     const HeadlandFrame& frame, const LineFit2D& wall, double edge_v, std::vector<EdgeRow>* rows) {
  // The rows' axis from their line fits and the rear wall's normal; offsets are measured across it (rows are
  // parallel): a short piece of a row with a gap has a poor direction of its own, but its cells still say
  // where it is.
  Eigen::Vector2d row_direction = Eigen::Vector2d::Zero();
  for (const auto& r : *rows) row_direction += r.fit.direction * static_cast<double>(r.fit.count);
  row_direction += frame.v * static_cast<double>(wall.count);
  row_direction.normalize();
  const Eigen::Vector2d across(row_direction.y(), -row_direction.x());
  std::vector<RowProfile> profiles;
  std::vector<double> widths, slopes, slope_sigmas;
  for (const auto& r : *rows) {
    const Eigen::Vector2d start = frame.toMap(r.u, edge_v);
    profiles.push_back(measureRowProfile(input, start, row_direction, 0.2, 3.0));
    const RowProfile clean = measureRowProfile(cleaned, start, row_direction, 0.2, 3.0);
    slopes.push_back(clean.slope);
    slope_sigmas.push_back(clean.slope_sigma);
    if (profiles.back().bothFaces()) widths.push_back(profiles.back().hi_face_m - profiles.back().lo_face_m);
  }
  const bool width_known = !widths.empty();
  const double row_width = median(widths);
  int rows_one_face = 0;
  for (std::size_t k = 0; k < rows->size(); ++k) {
    EdgeRow& r = (*rows)[k];
    const RowProfile& p = profiles[k];
    r.direction = r.fit.direction;
    if (p.cells < 3) continue;
    double centre = p.mean_m;
    if (p.bothFaces()) {
      centre = 0.5 * (p.lo_face_m + p.hi_face_m);
    } else if (width_known && (p.loSeen() || p.hiSeen())) {
      centre = p.hiSeen() ? p.hi_face_m - 0.5 * row_width : p.lo_face_m + 0.5 * row_width;
    } else {
      ++rows_one_face;
    }
    r.u += centre / std::max(0.5, across.dot(frame.u));
    r.d_min = p.d_min - centre - 0.5 * cleaned.resolution_m;
    r.d_max = p.d_max - centre + 0.5 * cleaned.resolution_m;
    if (std::isfinite(slope_sigmas[k])) {
      r.direction = (row_direction + slopes[k] * across).normalized();
      r.direction_sigma = slope_sigmas[k];
    }
  }
  return rows_one_face;
}

Eigen::Vector2d meanRowDirection(const std::vector<EdgeRow>& rows) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  const bool faces_fix_heading =
      std::all_of(rows.begin(), rows.end(), [](const EdgeRow& r) { return std::isfinite(r.direction_sigma); });
  for (const auto& r : rows)
    sum += faces_fix_heading ? Eigen::Vector2d(r.direction / (r.direction_sigma * r.direction_sigma))
                             : Eigen::Vector2d(r.fit.direction * static_cast<double>(r.fit.count));
  return sum.normalized();
}

}  // namespace greenhouse_rail_nav
