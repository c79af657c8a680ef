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

}  // namespace

std::vector<double> rowRunStarts(const OccupancyMap& map, const HeadlandFrame& frame, double u0, double slope,
                                 double v_from, double v_to, double* far_v, double row_half_width_m,
                                 double clutter_reach_m, double max_gap_m, double min_run_m) {
  const double step = map.resolution;
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

SideScan scanToSideWall(const OccupancyMap& map, const HeadlandFrame& frame, double u_start, double edge_v,
                        double direction, double min_support, double max_travel_m) {
  SideScan scan;
  const double step = 0.5 * map.resolution;
  const int lines = std::clamp(static_cast<int>(edge_v / 0.1), 10, 80);
  struct Stop {
    double distance;
    bool occupied;
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
  const double agree = std::max(0.06, 2.5 * map.resolution);
  const int needed = std::max(3, static_cast<int>(std::ceil(min_support * lines)));
  for (const double h : occupied) {
    std::vector<double> at;
    int occupied_at = 0, beyond = 0;
    for (const auto& s : stops) {
      if (std::abs(s.distance - h) <= agree) {
        at.push_back(s.distance);
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
    break;
  }
  return scan;
}

}  // namespace greenhouse_rail_nav
