#include "greenhouse_rail_nav/headland_scan.h"

#include <algorithm>
#include <cmath>

namespace greenhouse_rail_nav {
namespace {

constexpr int kOccupied = 65;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Where a wall's face lies along a scanline by the map's cell surface: the mean of the beam ends (weighted by their
/// number) in the cells from 1.5 cells in front of the stop to 2.5 behind it and within a cell of the scanline.
/// Range noise puts some of the ends of a wall whose face is near a cell boundary into the cell in front, which is
/// then drawn occupied: the first occupied cell is up to a cell in front of the face, the mean of the ends is not.
/// NaN without a surface or with fewer than 3 ends there.
double surfaceFaceU(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, double face_u, double v,
                    double direction) {
  if (map.surface.empty()) return NAN;
  const double res = map.resolution_m;
  std::vector<std::size_t> seen;
  double sum = 0.0, weight = 0.0;
  for (double du = -1.5 * res; du <= 2.5 * res + 1e-9; du += 0.5 * res) {
    for (double dv = -res; dv <= res + 1e-9; dv += 0.5 * res) {
      int c = 0, r = 0;
      if (!map.worldToCell(frame.toMap(face_u + direction * du, v + dv), &c, &r)) continue;
      const std::size_t i = static_cast<std::size_t>(r) * map.width + c;
      if (std::find(seen.begin(), seen.end(), i) != seen.end()) continue;
      seen.push_back(i);
      const float hits = map.surface.hits[i];
      if (!(hits > 0.0f)) continue;
      sum += hits * frame.toLocal(map.surface.mean_m[i].cast<double>()).x();
      weight += hits;
    }
  }
  return weight >= 3.0 ? sum / weight : NAN;
}

}  // namespace

std::vector<double> rowRunStarts(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, double u0,
                                 double slope, double v_from, double v_to, double* far_v, double row_half_width_m,
                                 double clutter_reach_m, double max_gap_m, double min_run_m) {
  const double step = map.resolution_m;
  std::vector<double> starts;
  *far_v = v_from;
  bool in_run = false;
  double run_start = 0.0, last_row = -1e9;
  auto close_run = [&]() {
    if (in_run && last_row - run_start >= min_run_m) starts.push_back(run_start);
    in_run = false;
  };
  for (double v = v_from; v <= v_to; v += step) {
    const double u_line = u0 + slope * v;
    bool narrow = false, wide = false;
    for (double d = -clutter_reach_m; d <= clutter_reach_m + 1e-9; d += 0.5 * step) {
      if (map.valueAt(frame.toMap(u_line + d, v)) < kOccupied) continue;
      if (std::abs(d) <= row_half_width_m) {
        narrow = true;
      } else {
        wide = true;
      }
    }
    if (wide) {
      close_run();
      continue;
    }
    if (!narrow) {
      if (in_run && v - last_row > max_gap_m) close_run();
      continue;
    }
    if (!in_run) {
      in_run = true;
      run_start = v - 0.5 * step;  // the row starts at the near face of its first cell
    }
    last_row = v;
    *far_v = v;
  }
  close_run();
  return starts;
}

RowProfile measureRowProfile(const thorvald_map::OccupancyGrid& map, const Eigen::Vector2d& start,
                             const Eigen::Vector2d& along, double half_width_m, double length_m) {
  RowProfile out;
  const Eigen::Vector2d across(along.y(), -along.x());
  const double res = map.resolution_m, t_from = -0.05;
  // Cells of the band, from the grid cells under its bounding box.
  int c0 = map.width, c1 = -1, r0 = map.height, r1 = -1;
  for (const double t : {t_from, length_m}) {
    for (const double d : {-half_width_m, half_width_m}) {
      const Eigen::Vector2d g = map.origin.inverse().transformPoint(start + t * along + d * across) / res;
      c0 = std::min(c0, static_cast<int>(std::floor(g.x())) - 1);
      c1 = std::max(c1, static_cast<int>(std::ceil(g.x())) + 1);
      r0 = std::min(r0, static_cast<int>(std::floor(g.y())) - 1);
      r1 = std::max(r1, static_cast<int>(std::ceil(g.y())) + 1);
    }
  }
  c0 = std::max(c0, 0);
  r0 = std::max(r0, 0);
  c1 = std::min(c1, map.width - 1);
  r1 = std::min(r1, map.height - 1);
  const int stations = std::max(1, static_cast<int>(std::ceil((length_m - t_from) / res)));
  struct Station {
    bool any = false;
    double t = 0.0, lo = 0.0, hi = 0.0;
    Eigen::Vector2d lo_p, hi_p;
  };
  std::vector<Station> at(static_cast<std::size_t>(stations));
  double sum = 0.0;
  out.d_min = INFINITY;
  out.d_max = -INFINITY;
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      if (map.at(c, r) < kOccupied) continue;
      const Eigen::Vector2d p = map.cellCentre(c, r);
      const double t = along.dot(p - start), d = across.dot(p - start);
      if (t < t_from || t > length_m || std::abs(d) > half_width_m) continue;
      ++out.cells;
      sum += d;
      out.d_min = std::min(out.d_min, d);
      out.d_max = std::max(out.d_max, d);
      auto& s = at[static_cast<std::size_t>(std::clamp(static_cast<int>((t - t_from) / res), 0, stations - 1))];
      if (!s.any || d < s.lo) {
        s.lo = d;
        s.lo_p = p;
      }
      if (!s.any || d > s.hi) {
        s.hi = d;
        s.hi_p = p;
      }
      s.t = s.any ? std::min(s.t, t) : t;
      s.any = true;
    }
  }
  if (out.cells == 0) {
    out.d_min = out.d_max = 0.0;
    return out;
  }
  out.mean_m = sum / out.cells;
  // A face is seen where free floor lies right beyond the outermost cell (within two cells: the laser's
  // hits blur a face by about one): an unknown cell there is the row's inside or the side no laser saw.
  auto floor_beyond = [&](const Eigen::Vector2d& p, double dir) {
    for (int k = 1; k <= 2; ++k) {
      const std::int8_t v = map.valueAt(p + dir * k * res * across);
      if (v >= 0 && v < 25) return true;
      if (v >= kOccupied) return false;
    }
    return false;
  };
  std::vector<double> lo, hi;
  std::vector<std::pair<double, double>> lo_pts, hi_pts;
  for (const auto& s : at) {
    if (!s.any) continue;
    ++out.stations;
    if (floor_beyond(s.lo_p, -1.0)) {
      lo.push_back(s.lo);
      lo_pts.emplace_back(s.t, s.lo);
    }
    if (floor_beyond(s.hi_p, +1.0)) {
      hi.push_back(s.hi);
      hi_pts.emplace_back(s.t, s.hi);
    }
  }
  out.lo_stations = static_cast<int>(lo.size());
  out.hi_stations = static_cast<int>(hi.size());
  out.lo_face_m = median(lo);
  out.hi_face_m = median(hi);
  // Direction from the faces beyond the row's front (a round or square front is no evidence of it): each
  // face's offsets about its own median against t, one least-squares slope over both.
  const double front = (out.bothFaces() ? out.hi_face_m - out.lo_face_m : 0.0) + res;
  double n = 0, st = 0, sd = 0, stt = 0, std_ = 0;
  std::vector<std::pair<double, double>> pts;
  for (const auto& q : lo_pts)
    if (q.first > front) pts.emplace_back(q.first, q.second - out.lo_face_m);
  for (const auto& q : hi_pts)
    if (q.first > front) pts.emplace_back(q.first, q.second - out.hi_face_m);
  for (const auto& q : pts) {
    n += 1;
    st += q.first;
    sd += q.second;
    stt += q.first * q.first;
    std_ += q.first * q.second;
  }
  const double den = n * stt - st * st;
  if (n >= 5 && den > 1e-12) {
    out.slope = (n * std_ - st * sd) / den;
    const double b = (sd - out.slope * st) / n;
    double rss = 0.0;
    for (const auto& q : pts) rss += std::pow(q.second - b - out.slope * q.first, 2);
    // Residuals at least a cell's quantisation (res / sqrt(12)).
    const double var = std::max(rss / (n - 2), res * res / 12.0);
    out.slope_sigma = std::sqrt(var * n / den);
  }
  return out;
}

SideScan scanToSideWall(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, double u_start,
                        double edge_v, double direction, double min_support, double max_travel_m) {
  SideScan scan;
  const double step = 0.5 * map.resolution_m;
  const int lines = std::clamp(static_cast<int>(edge_v / 0.1), 10, 80);
  struct Stop {
    double distance;
    bool occupied;
    double v = 0.0;
  };
  std::vector<Stop> stops;
  for (int k = 0; k < lines; ++k) {
    const double v = edge_v * (k + 0.5) / lines;
    // Walk on through obstacles with floor behind them (boxes, hoses, noise) to where the mapped floor
    // ends: the greenhouse's outside is never mapped as floor. The stop is the face after the last free
    // sample; it is a wall when an occupied cell follows that sample (a door leads into unknown at once).
    Stop stop{max_travel_m, false};
    double last_free = -step;
    bool blocked = false, blocked_by_occupied = false;
    for (double travelled = 0.0; travelled < max_travel_m; travelled += step) {
      const std::int8_t value = map.valueAt(frame.toMap(u_start + direction * travelled, v));
      if (value < 0) {
        stop = {std::max(0.0, last_free + 0.5 * step), blocked ? blocked_by_occupied : false};
        break;
      }
      if (value >= kOccupied) {
        if (!blocked) blocked_by_occupied = true;
        blocked = true;
      } else {
        last_free = travelled;
        blocked = false;
        blocked_by_occupied = false;
      }
    }
    if (blocked && stop.distance >= max_travel_m) stop = {std::max(0.0, last_free + 0.5 * step), blocked_by_occupied};
    if (stop.occupied) {
      const double face_u = surfaceFaceU(map, frame, u_start + direction * stop.distance, v, direction);
      const double d = direction * (face_u - u_start);
      if (std::isfinite(d) && std::abs(d - stop.distance) <= 2.0 * map.resolution_m) stop.distance = d;
    }
    stop.v = v;
    stops.push_back(stop);
  }
  scan.scanlines = lines;
  std::vector<double> distances;
  for (const auto& s : stops) distances.push_back(s.distance);
  scan.floor_extent_m = median(distances);
  // Candidate walls from the farthest occupied stop inwards.
  std::vector<double> occupied;
  for (const auto& s : stops)
    if (s.occupied) occupied.push_back(s.distance);
  std::sort(occupied.rbegin(), occupied.rend());
  const double agree = std::max(0.06, 2.5 * map.resolution_m);
  const int needed = std::max(3, static_cast<int>(std::ceil(min_support * lines)));
  for (const double h : occupied) {
    std::vector<double> at;
    std::vector<Eigen::Vector2d> wall_points;  // (v, distance) of the stops at the wall
    int occupied_at = 0, beyond = 0;
    for (const auto& s : stops) {
      if (std::abs(s.distance - h) <= agree) {
        at.push_back(s.distance);
        if (s.occupied) wall_points.emplace_back(s.v, s.distance);
        occupied_at += s.occupied;
      } else if (s.distance > h) {
        ++beyond;
      }
    }
    if (occupied_at < needed) continue;
    scan.at_wall = static_cast<int>(at.size());
    scan.beyond_wall = beyond;
    // Floor behind a line that most scanlines stop at: an obstacle, not the greenhouse's wall.
    scan.wall_found = beyond <= std::max(1, lines / 10);
    scan.wall_u = u_start + direction * median(at);
    // Where the wall is at the edge, which is where it bounds the rail sets: a wall a few milliradians off
    // square to the rear wall (a greenhouse, or its map, is never exactly rectangular) is centimetres off
    // its median over the headland there. A line through the stops at the wall, evaluated at the edge.
    if (wall_points.size() >= 5) {
      double n = 0, sv = 0, sd = 0, svv = 0, svd = 0;
      for (const auto& q : wall_points) {
        n += 1;
        sv += q.x();
        sd += q.y();
        svv += q.x() * q.x();
        svd += q.x() * q.y();
      }
      const double den = n * svv - sv * sv;
      if (den > 1e-9 * n * n) {
        const double slope = (n * svd - sv * sd) / den, offset = (sd - slope * sv) / n;
        // Only a wall close to square: a steeper fit is scanlines stopping at different things.
        if (std::abs(slope) < 0.05) scan.wall_u = u_start + direction * (offset + slope * edge_v);
      }
    }
    break;
  }
  return scan;
}

}  // namespace greenhouse_rail_nav
