#include "greenhouse_rail_nav/obstacle_zones.h"

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
  if (!(headland_radius_m >= 0.0)) e << "headland_radius must be >= 0 [m]; ";
  if (!(map_clearance_m >= 0.0)) e << "map_clearance must be >= 0 [m]; ";
  if (!(row_half_width_m > 0.0)) e << "row_half_width must be > 0 [m]; ";
  if (!(end_tolerance_m >= 0.0)) e << "end_tolerance must be >= 0 [m]; ";
  if (!(row_ahead_m > 0.0)) e << "row_ahead must be > 0 [m]; ";
  if (!(end_half_angle_rad > 0.0 && end_half_angle_rad < 0.5)) e << "end_half_angle must be in (0, 0.5) [rad]; ";
  if (!(rear_stop_range_m >= 0.0)) e << "rear_stop_range must be >= 0 [m]; ";
  if (!(clear_time_s >= 0.0)) e << "clear_time must be >= 0 [s]; ";
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
  double range = 0.0;
  for (const ScanPoint& q : pts) {
    c.x += q.x / pts.size();
    c.y += q.y / pts.size();
    c.near_x = std::min(c.near_x, q.x);
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
  // How far the points bulge from the chord between the first and the last: a person's body is round, the face of
  // a trolley or a crate is flat.
  const double cx = pts.back().x - pts.front().x, cy = pts.back().y - pts.front().y, chord = std::hypot(cx, cy);
  for (const ScanPoint& q : pts)
    if (chord > 1e-6)
      c.depth = std::max(c.depth, std::fabs(cx * (q.y - pts.front().y) - cy * (q.x - pts.front().x)) / chord);
  c.person = c.width >= p.person_min_width_m && c.width <= p.person_max_width_m && c.depth >= p.person_min_depth_m;
  return c;
}

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

void rowZone(const std::vector<ScanPoint>& points, double lidar_x, const ZoneContext& ctx, const ZoneParams& p,
             ZoneVerdict* v) {
  const double r = forwardMedian(points, lidar_x, p.end_half_angle_rad);
  const bool length_known = ctx.row_end_m > 0.0;
  const double end_from = ctx.row_end_m - p.end_tolerance_m;  // base_link x from which a return is the far end
  std::vector<ScanPoint> corridor;
  for (const ScanPoint& q : points)
    if (q.x > 0.0 && std::fabs(q.y) < p.row_half_width_m) corridor.push_back(q);
  v->clusters = clusterScan(corridor, p, lidar_x);
  for (const PointCluster& c : v->clusters) {
    const bool obstacle = length_known && c.near_x < end_from && c.near_x < p.row_ahead_m;
    v->in_zone.push_back(obstacle);
    if (obstacle && !v->blocked) {
      v->blocked = true;
      v->person = c.person;
      v->why = where(c.person ? "a person in the row ahead" : "an obstacle in the row ahead", c);
    } else if (obstacle && c.person) {
      v->person = true;
    }
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
    for (double r : rear_ranges) {
      if (std::isfinite(r) && r < p.rear_stop_range_m && !v.blocked) {
        std::ostringstream o;
        o.precision(2);
        o << std::fixed << "something " << r << " m behind the robot";
        v.blocked = true;
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

bool ZoneHold::update(bool blocked, double t_s) {
  if (blocked) {
    last_blocked_s_ = t_s;
    holding_ = true;
  } else if (holding_ && t_s - last_blocked_s_ >= clear_time_s_) {
    holding_ = false;
  }
  return holding_;
}

}  // namespace greenhouse_rail_nav
