#include "greenhouse_rail_nav/obstacle_zones.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace greenhouse_rail_nav {

std::string ZoneParams::validate() const {
  std::ostringstream e;
  if (!(cluster_gap_m > 0.0)) e << "cluster_gap must be > 0 [m]; ";
  if (min_cluster_points < 1) e << "min_cluster_points must be >= 1; ";
  if (!(person_min_width_m >= 0.0 && person_max_width_m > person_min_width_m))
    e << "person widths must be 0 <= min < max [m]; ";
  if (!(person_min_depth_m >= 0.0)) e << "person_min_depth must be >= 0 [m]; ";
  if (!(person_max_fit_rms_m > 0.0)) e << "person_max_fit_rms must be > 0 [m]; ";
  if (!(person_fit_outlier_m > 0.0)) e << "person_fit_outlier must be > 0 [m]; ";
  if (!(person_min_inliers > 0.0 && person_min_inliers <= 1.0)) e << "person_min_inliers must be in (0, 1]; ";
  if (person_confirm_scans < 1) e << "person_confirm_scans must be >= 1; ";
  if (!(person_confirm_radius_m > 0.0)) e << "person_confirm_radius must be > 0 [m]; ";
  if (!(headland_radius_m >= 0.0)) e << "headland_radius must be >= 0 [m]; ";
  if (!(map_clearance_m >= 0.0)) e << "map_clearance must be >= 0 [m]; ";
  if (!(row_half_width_m > 0.0)) e << "row_half_width must be > 0 [m]; ";
  if (!(row_edge_band_m >= 0.0)) e << "row_edge_band must be >= 0 [m]; ";
  if (!(row_lamps_radius_m >= 0.0)) e << "row_lamps_radius must be >= 0 [m]; ";
  if (!(row_ends_margin_m >= 0.0)) e << "row_ends_margin must be >= 0 [m]; ";
  if (!(end_tolerance_m >= 0.0)) e << "end_tolerance must be >= 0 [m]; ";
  if (!(row_ahead_m > 0.0)) e << "row_ahead must be > 0 [m]; ";
  if (!(end_half_angle_rad > 0.0 && end_half_angle_rad < 0.5)) e << "end_half_angle must be in (0, 0.5) [rad]; ";
  if (!(rear_stop_range_m >= 0.0)) e << "rear_stop_range must be >= 0 [m]; ";
  if (!(rear_clearance_m >= 0.0)) e << "rear_clearance must be >= 0 [m]; ";
  if (!(behind_wait_s >= 0.0)) e << "behind_wait must be >= 0 [s]; ";
  if (!(clear_time_s >= 0.0)) e << "clear_time must be >= 0 [s]; ";
  if (!(structure_min_length_m >= 0.0)) e << "structure_min_length must be >= 0 [m] (0: off); ";
  if (!(structure_tolerance_m > 0.0)) e << "structure_tolerance must be > 0 [m]; ";
  if (!(structure_gap_m > 0.0)) e << "structure_gap must be > 0 [m]; ";
  if (!(structure_max_angle_rad > 0.0 && structure_max_angle_rad < 1.5))
    e << "structure_max_angle must be in (0, 1.5) [rad]; ";
  return e.str();
}

const char* toString(ZonePhase phase) {
  switch (phase) {
    case ZonePhase::kHeadland:
      return "headland";
    case ZonePhase::kRow:
      return "row";
    case ZonePhase::kReverse:
      return "reverse";
    default:
      return "idle";
  }
}

namespace {

PointCluster summarise(const std::vector<ScanPoint>& pts, const ZoneParams& p, double origin_x) {
  PointCluster c;
  c.points = static_cast<int>(pts.size());
  c.near_x = pts.front().x;
  c.inner_y = std::fabs(pts.front().y);
  double range = 0.0;
  for (const ScanPoint& q : pts) {
    c.x += q.x / pts.size();
    c.y += q.y / pts.size();
    c.near_x = std::min(c.near_x, q.x);
    c.inner_y = std::min(c.inner_y, std::fabs(q.y));
    range += std::hypot(q.x - origin_x, q.y) / pts.size();
  }
  // The width across the beams (angle spanned times the mean range): a body's face, not a streak of mixed pixels
  // along the beams at an edge (the lidar's returns between a near edge and what lies behind it).
  double a_min = 1e9, a_max = -1e9;
  for (const ScanPoint& q : pts) {
    const double a = std::atan2(q.y, q.x - origin_x);
    a_min = std::min(a_min, a), a_max = std::max(a_max, a);
  }
  c.width = range * (a_max - a_min);
  if (c.width < p.person_min_width_m || c.width > p.person_max_width_m) return c;
  // A person's body is round and bulges towards the lidar; the face of a trolley or a crate is flat, its corner two
  // straight faces, and the mixed pixels at an edge lie behind it: a circle must fit, its outliers left out.
  c.person = c.points < kMinFitPoints || fitRoundBody(pts, p, origin_x, &c);
  return c;
}

struct Circle {
  double x = 0.0, y = 0.0, r = 0.0;
};

/// Least-squares circle through the points with use[i] (algebraic fit on coordinates about their mean).
bool fitCircle(const std::vector<ScanPoint>& pts, const std::vector<bool>& use, Circle* out) {
  double mx = 0.0, my = 0.0;
  int n = 0;
  for (size_t i = 0; i < pts.size(); ++i)
    if (use[i]) mx += pts[i].x, my += pts[i].y, ++n;
  if (n < kMinFitPoints) return false;
  mx /= n, my /= n;
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < pts.size(); ++i) {
    if (!use[i]) continue;
    const Eigen::Vector3d row(2.0 * (pts[i].x - mx), 2.0 * (pts[i].y - my), 1.0);
    a += row * row.transpose();
    b += row * (std::pow(pts[i].x - mx, 2) + std::pow(pts[i].y - my, 2));
  }
  const Eigen::Vector3d s = a.ldlt().solve(b);
  const double r2 = s(2) + s(0) * s(0) + s(1) * s(1);
  if (!s.allFinite() || !(r2 > 0.0)) return false;
  *out = {s(0) + mx, s(1) + my, std::sqrt(r2)};
  return true;
}

}  // namespace

bool fitRoundBody(const std::vector<ScanPoint>& pts, const ZoneParams& p, double origin_x, PointCluster* c) {
  std::vector<bool> use(pts.size(), true);
  Circle k;
  for (int pass = 0; pass < 3; ++pass) {
    if (!fitCircle(pts, use, &k)) return false;
    for (size_t i = 0; i < pts.size(); ++i)
      use[i] = std::fabs(std::hypot(pts[i].x - k.x, pts[i].y - k.y) - k.r) <= p.person_fit_outlier_m;
  }
  int n = 0;
  double sq = 0.0, near = 1e18, a_min = 1e9, a_max = -1e9;
  ScanPoint first, last;
  for (size_t i = 0; i < pts.size(); ++i) {
    if (!use[i]) continue;
    const ScanPoint& q = pts[i];
    ++n;
    sq += std::pow(std::hypot(q.x - k.x, q.y - k.y) - k.r, 2);
    near = std::min(near, std::hypot(q.x - origin_x, q.y));
    const double a = std::atan2(q.y, q.x - origin_x);
    if (a < a_min) a_min = a, first = q;
    if (a > a_max) a_max = a, last = q;
  }
  if (n < kMinFitPoints) return false;
  c->fit_radius = k.r;
  c->fit_rms = std::sqrt(sq / n);
  c->fit_inliers = static_cast<double>(n) / pts.size();
  // The arc's bulge from the chord between its extreme inliers; none when the centre is on the lidar's side.
  const double half_chord = 0.5 * std::hypot(last.x - first.x, last.y - first.y);
  const bool convex = std::hypot(k.x - origin_x, k.y) > near;
  c->depth = convex ? k.r - std::sqrt(std::max(0.0, k.r * k.r - half_chord * half_chord)) : 0.0;
  return c->fit_rms <= p.person_max_fit_rms_m && c->fit_inliers >= p.person_min_inliers &&
         c->depth >= p.person_min_depth_m;
}

namespace {

/// Median range from the lidar of the points within half_angle of its axis; NaN without any.
double forwardMedian(const std::vector<ScanPoint>& points, double lidar_x, double half_angle) {
  std::vector<double> ahead;
  for (const ScanPoint& q : points) {
    const double dx = q.x - lidar_x;
    if (dx > 0.0 && std::fabs(std::atan2(q.y, dx)) <= half_angle) ahead.push_back(std::hypot(dx, q.y));
  }
  if (ahead.empty()) return std::numeric_limits<double>::quiet_NaN();
  auto mid = ahead.begin() + static_cast<std::ptrdiff_t>(ahead.size() / 2);
  std::nth_element(ahead.begin(), mid, ahead.end());
  return *mid;
}

std::string where(const char* what, const PointCluster& c) {
  std::ostringstream o;
  o.precision(2);
  o << std::fixed << what << " at (" << c.x << ", " << c.y << ") m";
  return o.str();
}

void rowZone(const std::vector<ScanPoint>& all_points, double lidar_x, const ZoneContext& ctx, const ZoneParams& p,
             ZoneVerdict* v) {
  // The lines the greenhouse runs along the rows are no obstacle and no far end.
  const std::vector<bool> structure = rowStructure(all_points, p);
  std::vector<ScanPoint> points;
  for (std::size_t i = 0; i < all_points.size(); ++i)
    if (!structure[i]) points.push_back(all_points[i]);
  const double r = forwardMedian(points, lidar_x, p.end_half_angle_rad);
  const bool length_known = ctx.row_end_m > 0.0;
  const double end_from = ctx.row_end_m - p.end_tolerance_m;  // base_link x from which a return is the far end
  std::vector<ScanPoint> corridor, beside;
  const double reach = p.row_lamps_radius_m + 1.0;  // a person's centroid can be this far and their centre within
  for (const ScanPoint& q : points) {
    if (q.x > 0.0 && std::fabs(q.y) < p.row_half_width_m + p.row_edge_band_m) corridor.push_back(q);
    if (!(q.x > 0.0 && std::fabs(q.y) < p.row_half_width_m) && ctx.lamps && p.row_lamps_radius_m > 0.0 &&
        std::hypot(q.x, q.y) < reach)
      beside.push_back(q);
  }
  // A cluster in the corridor reaches into it with one point at least; the band beside it only completes bodies.
  for (const PointCluster& c : clusterScan(corridor, p, lidar_x))
    if (c.inner_y < p.row_half_width_m) v->clusters.push_back(c);
  for (const PointCluster& c : v->clusters) {
    // Short of the end anything is an obstacle; in the end's tolerance, short of the rails' end, a person still is
    // one (the end is flat), when seen with enough points to tell (a far wall's few noisy returns can fit a circle).
    const bool person_at_end = c.person && c.points >= 2 * kMinFitPoints && c.near_x < ctx.row_end_m;
    const bool obstacle = length_known && c.near_x < p.row_ahead_m && (c.near_x < end_from || person_at_end);
    v->in_zone.push_back(obstacle);
    if (obstacle && !v->blocked) {
      v->blocked = true;
      v->person = c.person;
      v->why = where(c.person ? "a person in the row ahead" : "an obstacle in the row ahead", c);
    } else if (obstacle && c.person) {
      v->person = true;
    }
  }
  // People beside the corridor within the lamps' reach: in the zone, blocking once PersonConfirmation confirms them.
  for (PointCluster c : clusterScan(beside, p, lidar_x)) {
    if (!c.person || std::hypot(c.x, c.y) + 0.5 * c.width >= p.row_lamps_radius_m) continue;
    const bool at_end = length_known && std::fabs(c.x - ctx.row_end_m) < p.row_ends_margin_m;
    const bool at_start = ctx.row_along_m >= 0.0 && std::fabs(c.x + ctx.row_along_m) < p.row_ends_margin_m;
    if (at_end || at_start) continue;
    c.beside = true;
    v->clusters.push_back(c);
    v->in_zone.push_back(true);
  }
  if (!std::isfinite(r)) return;
  if (!length_known || lidar_x + r >= end_from) {
    v->end_range_m = r;
  } else if (!v->blocked && lidar_x + r < p.row_ahead_m) {
    // A return straight ahead short of the set's length, too small to make a cluster: never the end.
    std::ostringstream o;
    o.precision(2);
    o << std::fixed << "something in the row ahead at " << lidar_x + r << " m, short of the end at " << ctx.row_end_m
      << " m";
    v->blocked = true;
    v->why = o.str();
  }
}

}  // namespace

std::vector<bool> rowStructure(const std::vector<ScanPoint>& points, const ZoneParams& p) {
  std::vector<bool> out(points.size(), false);
  if (!(p.structure_min_length_m > 0.0)) return out;
  const auto straight = [&](std::size_t i, std::size_t j) {  // every point of i..j within tolerance of the chord
    const Eigen::Vector2d a(points[i].x, points[i].y), b(points[j].x, points[j].y);
    const Eigen::Vector2d d = b - a;
    const double len = d.norm();
    if (len < 1e-9) return true;
    for (std::size_t k = i + 1; k < j; ++k) {
      const Eigen::Vector2d q(points[k].x - a.x(), points[k].y - a.y());
      if (std::fabs(d.x() * q.y() - d.y() * q.x()) / len > p.structure_tolerance_m) return false;
    }
    return true;
  };
  std::size_t i = 0;
  while (i + 1 < points.size()) {
    // The longest straight run from i of neighbours closer than structure_gap.
    std::size_t j = i;
    while (j + 1 < points.size() &&
           std::hypot(points[j + 1].x - points[j].x, points[j + 1].y - points[j].y) < p.structure_gap_m &&
           straight(i, j + 1))
      ++j;
    const double dx = points[j].x - points[i].x, dy = points[j].y - points[i].y;
    const double angle = std::atan2(std::fabs(dy), std::fabs(dx));  // from the robot's heading, either way along it
    const bool gap_ends_it = j + 1 >= points.size() || std::hypot(points[j + 1].x - points[j].x,
                                                                  points[j + 1].y - points[j].y) >= p.structure_gap_m;
    if (std::hypot(dx, dy) >= p.structure_min_length_m) {
      if (angle <= p.structure_max_angle_rad)
        for (std::size_t k = i; k <= j; ++k) out[k] = true;
      i = j + 1;  // a straight run: no part of it runs another way
    } else if (gap_ends_it) {
      i = j + 1;  // no run from inside it reaches past the gap
    } else {
      i += std::max<std::size_t>(1, (j - i) / 2);  // a bend: the next run may start within this one
    }
  }
  return out;
}

std::vector<PointCluster> clusterScan(const std::vector<ScanPoint>& points, const ZoneParams& p, double origin_x) {
  std::vector<PointCluster> out;
  std::vector<ScanPoint> cur;
  auto close = [&] {
    if (static_cast<int>(cur.size()) >= p.min_cluster_points) out.push_back(summarise(cur, p, origin_x));
    cur.clear();
  };
  for (const ScanPoint& q : points) {
    if (!cur.empty() && std::hypot(q.x - cur.back().x, q.y - cur.back().y) >= p.cluster_gap_m) close();
    cur.push_back(q);
  }
  if (!cur.empty()) close();
  return out;
}

ZoneVerdict evaluateZone(const std::vector<ScanPoint>& points, double lidar_x, const ZoneContext& ctx,
                         const ZoneParams& p, const KnownPoint& known, const std::vector<double>& rear_ranges) {
  ZoneVerdict v;
  if (ctx.phase == ZonePhase::kRow) {
    rowZone(points, lidar_x, ctx, p, &v);
    return v;
  }
  if (ctx.phase == ZonePhase::kReverse) {
    const double stop_m = ctx.reverse_left_m >= 0.0
                              ? std::min(p.rear_stop_range_m, ctx.reverse_left_m + p.rear_clearance_m)
                              : p.rear_stop_range_m;
    for (double r : rear_ranges) {
      if (std::isfinite(r) && r < stop_m && !v.blocked) {
        std::ostringstream o;
        o.precision(2);
        o << std::fixed << "something " << r << " m behind the robot";
        v.blocked = v.behind = true;
        v.why = o.str();
      }
    }
  }
  // Headland (and idle, and the lidar's view while reversing): people that are not part of the map, near the robot.
  std::vector<ScanPoint> unknown;
  for (const ScanPoint& q : points)
    if (!known || !known(q.x, q.y)) unknown.push_back(q);
  v.clusters = clusterScan(unknown, p, lidar_x);
  for (const PointCluster& c : v.clusters) {
    const bool in = c.person && std::hypot(c.x, c.y) < p.headland_radius_m;
    v.in_zone.push_back(in);
    if (!in) continue;
    v.person = true;
    if (!v.blocked) {
      v.blocked = true;
      v.why = where("a person near the robot", c);
    }
  }
  return v;
}

void PersonConfirmation::confirmRowPerson(const PointCluster& c, ZoneVerdict* v) {
  v->person = true;
  if (v->blocked) return;  // the corridor's reason comes first
  v->blocked = true;
  v->why = where("a person beside the robot, in the lamps' reach,", c);
}

void PersonConfirmation::apply(ZonePhase phase, ZoneVerdict* v) {
  const bool row = phase == ZonePhase::kRow;
  // In the row only the people beside the corridor wait for confirmation; the corridor's verdict stands as it is.
  const auto waits = [&](size_t i) {
    return v->in_zone[i] && v->clusters[i].person && (!row || v->clusters[i].beside);
  };
  if (scans_ <= 1) {
    seen_.clear();
    if (row)
      for (size_t i = 0; i < v->clusters.size(); ++i)
        if (waits(i)) confirmRowPerson(v->clusters[i], v);
    return;
  }
  std::vector<ScanPoint> now;
  for (size_t i = 0; i < v->clusters.size(); ++i)
    if (waits(i)) now.push_back({v->clusters[i].x, v->clusters[i].y});
  auto seenIn = [&](const std::vector<ScanPoint>& scan, const PointCluster& c) {
    for (const ScanPoint& q : scan)
      if (std::hypot(q.x - c.x, q.y - c.y) <= radius_m_) return true;
    return false;
  };
  bool any = false;
  for (size_t i = 0; i < v->clusters.size(); ++i) {
    if (!waits(i)) continue;
    bool confirmed = static_cast<int>(seen_.size()) >= scans_ - 1;
    for (const auto& scan : seen_) confirmed = confirmed && seenIn(scan, v->clusters[i]);
    v->in_zone[i] = confirmed;
    if (row) {
      if (confirmed) confirmRowPerson(v->clusters[i], v);
    } else if (confirmed && !any) {
      any = true;
      if (!v->behind) v->why = where("a person near the robot", v->clusters[i]);
    }
  }
  if (!row) {
    v->person = any;
    v->blocked = any || v->behind;
    if (!v->blocked) v->why.clear();
  }
  seen_.push_back(now);
  if (static_cast<int>(seen_.size()) > scans_ - 1) seen_.erase(seen_.begin());
}

bool ZoneHold::update(bool blocked, double t_s) {
  if (blocked) {
    last_blocked_s_ = t_s;
    holding_ = true;
  } else if (holding_ && t_s - last_blocked_s_ >= clear_time_s_) {
    holding_ = false;
  }
  return holding_;
}

bool notHeadland(const thorvald_map::OccupancyGrid& map, const thorvald_map::OccupancyGrid& keep_out, int reach_cells,
                 const Eigen::Vector2d& p_map) {
  int cx = 0, cy = 0;
  if (!map.worldToCell(p_map, &cx, &cy)) return true;  // outside the map: not headland
  if (map.at(cx, cy) == thorvald_map::kUnknown) return true;
  for (int dy = -reach_cells; dy <= reach_cells; ++dy)
    for (int dx = -reach_cells; dx <= reach_cells; ++dx)
      if (map.inside(cx + dx, cy + dy) && map.at(cx + dx, cy + dy) >= 50) return true;
  int kx = 0, ky = 0;
  return keep_out.width > 0 && keep_out.worldToCell(p_map, &kx, &ky) && keep_out.at(kx, ky) >= 65;
}

}  // namespace greenhouse_rail_nav
