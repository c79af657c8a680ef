#include "greenhouse_rail_nav/headland_scan.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

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

/// Sums of a least-squares line y = b + slope * x through (x, y) points.
struct LineSums {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  void add(double x, double y) {
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  double den() const { return n * sxx - sx * sx; }
  double slope() const { return (n * sxy - sx * sy) / den(); }
};

/// The band a row profile is measured in: `along` (unit) from `start` over [t_from, length_m], half_width_m
/// across it (along (along.y, -along.x)), and the grid cells under its bounding box.
struct RowBand {
  Eigen::Vector2d start, along, across;
  double half_width_m, length_m, t_from = -0.05;
  int c0, c1, r0, r1;
  int stations;  ///< one station per cell along the band

  RowBand(const thorvald_map::OccupancyGrid& map, const Eigen::Vector2d& start_, const Eigen::Vector2d& along_,
          double half_width, double length)
      : start(start_), along(along_), across(along_.y(), -along_.x()), half_width_m(half_width), length_m(length) {
    const double res = map.resolution_m;
    c0 = map.width, c1 = -1, r0 = map.height, r1 = -1;
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
    stations = std::max(1, static_cast<int>(std::ceil((length_m - t_from) / res)));
  }
};

/// The row's outermost occupied cells on both sides at one station along the band.
struct Station {
  bool any = false;
  double t = 0.0, lo = 0.0, hi = 0.0;
  Eigen::Vector2d lo_p, hi_p;
};

/// The occupied cells in the band: their count, mean offset and extent across (into `out`), and per station the
/// outermost cell on each side. With no cell the extent is 0.
std::vector<Station> collectStations(const thorvald_map::OccupancyGrid& map, const RowBand& b, RowProfile* out) {
  std::vector<Station> at(static_cast<std::size_t>(b.stations));
  double sum = 0.0;
  out->d_min = INFINITY;
  out->d_max = -INFINITY;
  for (int r = b.r0; r <= b.r1; ++r) {
    for (int c = b.c0; c <= b.c1; ++c) {
      if (map.at(c, r) < kOccupied) continue;
      const Eigen::Vector2d p = map.cellCentre(c, r);
      const double t = b.along.dot(p - b.start), d = b.across.dot(p - b.start);
      if (t < b.t_from || t > b.length_m || std::abs(d) > b.half_width_m) continue;
      ++out->cells;
      sum += d;
      out->d_min = std::min(out->d_min, d);
      out->d_max = std::max(out->d_max, d);
      const int k = std::clamp(static_cast<int>((t - b.t_from) / map.resolution_m), 0, b.stations - 1);
      auto& s = at[static_cast<std::size_t>(k)];
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
  if (out->cells == 0) {
    out->d_min = out->d_max = 0.0;
  } else {
    out->mean_m = sum / out->cells;
  }
  return at;
}

/// The faces of the row: a face is seen at a station where free floor lies right beyond its outermost cell
/// (within two cells: the laser's hits blur a face by about one); an unknown cell there is the row's inside or
/// the side no laser saw. Fills the station counts and the faces' medians; `lo_pts`, `hi_pts`: (t, offset) of
/// each seen face.
void measureFaces(const thorvald_map::OccupancyGrid& map, const RowBand& b, const std::vector<Station>& at,
                  RowProfile* out, std::vector<std::pair<double, double>>* lo_pts,
                  std::vector<std::pair<double, double>>* hi_pts) {
  auto floor_beyond = [&](const Eigen::Vector2d& p, double dir) {
    for (int k = 1; k <= 2; ++k) {
      const std::int8_t v = map.valueAt(p + dir * k * map.resolution_m * b.across);
      if (v >= 0 && v < 25) return true;
      if (v >= kOccupied) return false;
    }
    return false;
  };
  std::vector<double> lo, hi;
  for (const auto& s : at) {
    if (!s.any) continue;
    ++out->stations;
    if (floor_beyond(s.lo_p, -1.0)) {
      lo.push_back(s.lo);
      lo_pts->emplace_back(s.t, s.lo);
    }
    if (floor_beyond(s.hi_p, +1.0)) {
      hi.push_back(s.hi);
      hi_pts->emplace_back(s.t, s.hi);
    }
  }
  out->lo_stations = static_cast<int>(lo.size());
  out->hi_stations = static_cast<int>(hi.size());
  out->lo_face_m = median(lo);
  out->hi_face_m = median(hi);
}

/// The row's direction from the faces beyond its front (a round or square front is no evidence of it): each
/// face's offsets about its own median against t, one least-squares slope over both, with its standard error.
void fitFaceDrift(const std::vector<std::pair<double, double>>& lo_pts,
                  const std::vector<std::pair<double, double>>& hi_pts, double res, RowProfile* out) {
  const double front = (out->bothFaces() ? out->hi_face_m - out->lo_face_m : 0.0) + res;
  std::vector<std::pair<double, double>> pts;
  for (const auto& q : lo_pts)
    if (q.first > front) pts.emplace_back(q.first, q.second - out->lo_face_m);
  for (const auto& q : hi_pts)
    if (q.first > front) pts.emplace_back(q.first, q.second - out->hi_face_m);
  LineSums f;
  for (const auto& q : pts) f.add(q.first, q.second);
  const double den = f.den();
  if (!(f.n >= 5 && den > 1e-12)) return;
  out->slope = f.slope();
  const double b = (f.sy - out->slope * f.sx) / f.n;
  double rss = 0.0;
  for (const auto& q : pts) rss += std::pow(q.second - b - out->slope * q.first, 2);
  // Residuals at least a cell's quantisation (res / sqrt(12)).
  const double var = std::max(rss / (f.n - 2), res * res / 12.0);
  out->slope_sigma = std::sqrt(var * f.n / den);
}

/// Where one scanline across the headland stops, at its height v [m] along the headland.
struct ScanStop {
  double distance;
  bool occupied;  ///< stopped at an occupied cell (a wall's face) rather than at unknown space
  double v = 0.0;
};

/// Walks one scanline at height v from u_start in `direction` on through obstacles with floor behind them
/// (boxes, hoses, noise) to where the mapped floor ends: the greenhouse's outside is never mapped as floor. The
/// stop is the face after the last free sample; it is a wall when an occupied cell follows that sample (a door
/// leads into unknown at once), and then it is moved to the wall's cell surface where that agrees.
ScanStop walkScanline(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, double u_start, double v,
                      double direction, double max_travel_m) {
  const double step = 0.5 * map.resolution_m;
  ScanStop stop{max_travel_m, false};
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
  return stop;
}

/// Where a wall a few milliradians off square to the rear wall (a greenhouse, or its map, is never exactly
/// rectangular) meets the edge, which is where it bounds the rail sets: a line through the stops at the wall,
/// (v, distance), evaluated at edge_v. Empty with fewer than 5 stops, a degenerate fit, or a fit too steep to be
/// one wall (scanlines stopping at different things).
std::optional<double> wallDistanceAtEdge(const std::vector<Eigen::Vector2d>& wall_points, double edge_v) {
  if (wall_points.size() < 5) return std::nullopt;
  LineSums f;
  for (const auto& q : wall_points) f.add(q.x(), q.y());
  const double den = f.den();
  if (!(den > 1e-9 * f.n * f.n)) return std::nullopt;
  const double slope = f.slope(), offset = (f.sy - slope * f.sx) / f.n;
  if (!(std::abs(slope) < 0.05)) return std::nullopt;
  return offset + slope * edge_v;
}

/// The side wall among the stops: the farthest occupied stop at which at least min_support of the scanlines
/// stop together at an occupied cell. Fills the wall's fields of `scan` (left as they are when there is none).
void findSideWall(const std::vector<ScanStop>& stops, double res, double u_start, double edge_v, double direction,
                  double min_support, SideScan* scan) {
  const int lines = static_cast<int>(stops.size());
  std::vector<double> occupied;
  for (const auto& s : stops)
    if (s.occupied) occupied.push_back(s.distance);
  std::sort(occupied.rbegin(), occupied.rend());
  const double agree = std::max(0.06, 2.5 * res);
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
    scan->at_wall = static_cast<int>(at.size());
    scan->beyond_wall = beyond;
    // Floor behind a line that most scanlines stop at: an obstacle, not the greenhouse's wall.
    scan->wall_found = beyond <= std::max(1, lines / 10);
    scan->wall_u = u_start + direction * median(at);
    if (const auto d = wallDistanceAtEdge(wall_points, edge_v)) scan->wall_u = u_start + direction * *d;
    return;
  }
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
  const RowBand band(map, start, along, half_width_m, length_m);
  RowProfile out;
  const std::vector<Station> at = collectStations(map, band, &out);
  if (out.cells == 0) return out;
  std::vector<std::pair<double, double>> lo_pts, hi_pts;
  measureFaces(map, band, at, &out, &lo_pts, &hi_pts);
  fitFaceDrift(lo_pts, hi_pts, map.resolution_m, &out);
  return out;
}

SideScan scanToSideWall(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, double u_start,
                        double edge_v, double direction, double min_support, double max_travel_m) {
  SideScan scan;
  const int lines = std::clamp(static_cast<int>(edge_v / 0.1), 10, 80);
  std::vector<ScanStop> stops;
  for (int k = 0; k < lines; ++k) {
    const double v = edge_v * (k + 0.5) / lines;
    stops.push_back(walkScanline(map, frame, u_start, v, direction, max_travel_m));
  }
  scan.scanlines = lines;
  std::vector<double> distances;
  for (const auto& s : stops) distances.push_back(s.distance);
  scan.floor_extent_m = median(distances);
  findSideWall(stops, map.resolution_m, u_start, edge_v, direction, min_support, &scan);
  return scan;
}

}  // namespace greenhouse_rail_nav
