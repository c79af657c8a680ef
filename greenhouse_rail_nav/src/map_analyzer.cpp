#include "greenhouse_rail_nav/map_analyzer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "greenhouse_rail_nav/cell_clustering.h"

namespace greenhouse_rail_nav {
namespace {

double angleBetweenLines(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::acos(std::min(1.0, std::abs(a.dot(b))));
}

bool perpendicular(const LineFit2D& a, const LineFit2D& b, double tolerance) {
  return std::abs(M_PI / 2 - angleBetweenLines(a.direction, b.direction)) <= tolerance;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string fmt(double value, int decimals = 2) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(decimals);
  s << value;
  return s.str();
}

/// The headland frame: origin on the rear wall line, u along it, v into the rows.
struct HeadlandFrame {
  Eigen::Vector2d origin, u, v;
  Eigen::Vector2d toLocal(const Eigen::Vector2d& p) const { return {u.dot(p - origin), v.dot(p - origin)}; }
  Eigen::Vector2d toMap(double pu, double pv) const { return origin + pu * u + pv * v; }
};

/// Walks along the headland from an outer row outward; returns the u where the first occupied cell is
/// met, or NaN when the walk leaves the mapped area (unknown cell) without meeting a wall.
double walkToWall(const OccupancyMap& map, const HeadlandFrame& frame, double u_start, double v, double direction) {
  const double step = map.resolution * 0.5;
  const double limit = std::hypot(map.widthMeters(), map.heightMeters());
  for (double travelled = 0.0; travelled < limit; travelled += step) {
    const double u = u_start + direction * travelled;
    const std::int8_t value = map.valueAt(frame.toMap(u, v));
    if (value >= 65) return u - direction * 0.25 * map.resolution;
    if (value < 0) return std::nan("");
  }
  return std::nan("");
}

/// Side wall position from several walks across the headland at different depths. A wall stops every
/// walk at the same place; clutter stops only some, and earlier; a door lets a walk out into unknown
/// space. So the wall is the farthest place where at least two walks stop together, and more walks stop
/// there than escape.
bool findSideWall(const OccupancyMap& map, const HeadlandFrame& frame, double u_start, double edge_v, double direction,
                  double* wall_u) {
  std::vector<double> hits;
  const int walks = 9;
  for (int i = 1; i <= walks; ++i) {
    const double u = walkToWall(map, frame, u_start, edge_v * i / (walks + 1.0), direction);
    if (std::isfinite(u)) hits.push_back(u);
  }
  const int escaped = walks - static_cast<int>(hits.size());
  std::sort(hits.begin(), hits.end(), [direction](double a, double b) { return direction * a > direction * b; });
  const double agree = 2.0 * map.resolution;
  for (const double h : hits) {
    double sum = 0.0;
    int count = 0;
    for (const double other : hits) {
      if (std::abs(other - h) <= agree) {
        sum += other;
        ++count;
      }
    }
    if (count >= 2) {
      // Where most walks went on into unmapped space there is no wall, only something on the floor.
      if (count <= escaped) return false;
      *wall_u = sum / count;
      return true;
    }
  }
  return false;
}

}  // namespace

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
  return "";
}

MapAnalysis analyzeMap(const OccupancyMap& map, const MapAnalyzerParams& params) {
  MapAnalysis result;
  const auto clusters =
      clusterOccupiedCells(map, params.cluster_link_radius_m, static_cast<std::size_t>(params.min_cluster_cells));
  result.lines = extractLines(clusters, params.lines);
  const auto& lines = result.lines;
  const std::string found = "found " + std::to_string(clusters.size()) +
                            " clusters of >= " + std::to_string(params.min_cluster_cells) + " occupied cells and " +
                            std::to_string(lines.size()) + " straight lines";
  if (lines.empty()) {
    result.message = found + "; expected a rear wall and at least one row or ventilation line";
    return result;
  }

  // Rear wall: the line most other lines are perpendicular to (rows and side walls), longest on ties.
  int best_score = -1;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    int score = 0;
    for (std::size_t j = 0; j < lines.size(); ++j) {
      score += j != i && perpendicular(lines[i].fit, lines[j].fit, params.perpendicular_tolerance_rad);
    }
    if (score > best_score ||
        (score == best_score &&
         lines[i].fit.length() > lines[static_cast<std::size_t>(result.rear_wall)].fit.length())) {
      best_score = score;
      result.rear_wall = static_cast<int>(i);
    }
  }
  const LineFit2D& wall = lines[static_cast<std::size_t>(result.rear_wall)].fit;
  // The rows lie on the side of the rear wall where the perpendicular lines are.
  HeadlandFrame frame{wall.centroid, wall.direction, Eigen::Vector2d(-wall.direction.y(), wall.direction.x())};
  double side = 0.0;
  for (const auto& line : lines) {
    if (perpendicular(wall, line.fit, params.perpendicular_tolerance_rad)) side += frame.toLocal(line.fit.centroid).y();
  }
  if (side < 0.0) {
    frame.v = -frame.v;
  }
  frame.u = Eigen::Vector2d(frame.v.y(), -frame.v.x());  // u points right when looking into the rows
  result.into_rows = frame.v;

  // Row candidates: perpendicular lines that start well away from the rear wall, on the rows' side.
  struct Row {
    int line;
    double start_v;
  };
  std::vector<Row> candidates;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (static_cast<int>(i) == result.rear_wall ||
        !perpendicular(wall, lines[i].fit, params.perpendicular_tolerance_rad))
      continue;
    double start_v = std::numeric_limits<double>::max();
    for (const auto& p : lines[i].points) {
      if (std::abs(lines[i].fit.signedDistance(p)) <= params.lines.split_inlier_m * 1.5)
        start_v = std::min(start_v, frame.toLocal(p).y());
    }
    start_v -= 0.5 * map.resolution;  // the row starts at the near face of its first cell, not its centre
    if (start_v >= params.min_headland_depth_m) candidates.push_back({static_cast<int>(i), start_v});
  }
  const std::string wall_text = "rear wall of " + fmt(wall.length(), 1) + " m";
  if (candidates.empty()) {
    result.message = found + " (" + wall_text +
                     "), but none perpendicular to it starting >= " + fmt(params.min_headland_depth_m, 1) +
                     " m from it; expected at least one row or ventilation line perpendicular to the rear wall";
    return result;
  }
  // Headland edge: the start most rows agree on (ties: the nearest, since occlusion and gaps can only
  // make a row seem to start later), refined as the median of the agreeing starts.
  double seed_v = 0.0;
  std::size_t best_support = 0;
  for (const auto& c : candidates) {
    std::size_t support = 0;
    for (const auto& other : candidates) support += std::abs(other.start_v - c.start_v) <= params.edge_tolerance_m;
    if (support > best_support || (support == best_support && c.start_v < seed_v)) {
      best_support = support;
      seed_v = c.start_v;
    }
  }
  std::vector<double> starts;
  for (const auto& c : candidates)
    if (std::abs(c.start_v - seed_v) <= params.edge_tolerance_m) starts.push_back(c.start_v);
  const double edge_v = median(starts);
  Eigen::Vector2d row_direction = Eigen::Vector2d::Zero();
  std::vector<std::pair<double, int>> row_positions;  // u where each row meets the edge, line index
  for (const auto& c : candidates) {
    if (std::abs(c.start_v - edge_v) > params.edge_tolerance_m) {
      result.warnings.push_back("line starting " + fmt(c.start_v) + " m from the rear wall ignored: the edge is at " +
                                fmt(edge_v) + " m");
      continue;
    }
    LineFit2D fit = lines[static_cast<std::size_t>(c.line)].fit;
    if (fit.direction.dot(frame.v) < 0.0) fit.flip();
    row_direction += fit.direction * static_cast<double>(fit.count);
    // Intersection of the row line with the edge line v = edge_v.
    const Eigen::Vector2d c_local = frame.toLocal(fit.centroid);
    const double dv = fit.direction.dot(frame.v), du = fit.direction.dot(frame.u);
    row_positions.emplace_back(c_local.x() + (edge_v - c_local.y()) / dv * du, c.line);
  }
  if (row_positions.empty()) {
    result.message = found + " (" + wall_text + "), " + std::to_string(candidates.size()) +
                     " lines perpendicular to it but their starts disagree by more than " +
                     fmt(params.edge_tolerance_m) + " m; expected rows starting along one headland edge";
    return result;
  }
  std::sort(row_positions.begin(), row_positions.end());
  for (const auto& rp : row_positions) result.rows.push_back(rp.second);
  // The rear wall's normal measures the same greenhouse axis, from many more cells: it joins the mean.
  row_direction += frame.v * static_cast<double>(wall.count);
  row_direction.normalize();
  const double heading = std::atan2(row_direction.y(), row_direction.x());

  // Side walls beyond the outer rows, then every gap between neighbours holds round(gap / spacing) sets.
  double left_u = 0.0, right_u = 0.0;
  result.left_wall_found = findSideWall(map, frame, row_positions.front().first, edge_v, -1.0, &left_u);
  result.right_wall_found = findSideWall(map, frame, row_positions.back().first, edge_v, +1.0, &right_u);
  std::vector<double> positions;
  if (result.left_wall_found) positions.push_back(left_u);
  for (const auto& rp : row_positions) positions.push_back(rp.first);
  if (result.right_wall_found) positions.push_back(right_u);
  const double spacing = params.rail_set_spacing_m;
  std::vector<double> set_u;
  for (std::size_t k = 0; k + 1 < positions.size(); ++k) {
    const double gap = positions[k + 1] - positions[k];
    const long n = std::lround(gap / spacing);
    if (n == 0) {
      result.warnings.push_back("two lines only " + fmt(gap) + " m apart (spacing " + fmt(spacing) + " m)");
      continue;
    }
    if (std::abs(gap - n * spacing) > params.spacing_tolerance * spacing) {
      result.warnings.push_back("gap of " + fmt(gap) + " m is not a multiple of the spacing " + fmt(spacing) +
                                " m; assumed " + std::to_string(n) + " rail sets");
    }
    for (long j = 0; j < n; ++j) set_u.push_back(positions[k] + (j + 0.5) * gap / static_cast<double>(n));
  }
  result.edge_start = frame.toMap(positions.front(), edge_v);
  result.edge_end = frame.toMap(positions.back(), edge_v);
  result.left_wall = frame.toMap(left_u, edge_v);
  result.right_wall = frame.toMap(right_u, edge_v);
  for (const double u : set_u) {
    RailSetEstimate set;
    set.index = static_cast<int>(result.rail_sets.size());
    const Eigen::Vector2d origin = frame.toMap(u, edge_v);
    set.rail_frame = Pose2D(origin.x(), origin.y(), heading);
    set.target_pose = set.rail_frame.compose(params.target_in_rail);
    result.rail_sets.push_back(set);
  }
  result.ok = !result.rail_sets.empty();
  result.message = found + ": " + wall_text + ", " + std::to_string(result.rows.size()) +
                   " rows/ventilation lines, headland edge " + fmt(edge_v) + " m from the rear wall, side walls " +
                   (result.left_wall_found ? "left " : "") + (result.right_wall_found ? "right " : "") +
                   (result.left_wall_found || result.right_wall_found ? "found" : "not found") + ", " +
                   std::to_string(result.rail_sets.size()) + " rail sets";
  if (!result.ok) result.message += "; expected at least two lines (rows or walls) a rail-set spacing apart";
  return result;
}

}  // namespace greenhouse_rail_nav
