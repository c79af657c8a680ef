#include "greenhouse_rail_nav/rear_wall.h"

#include <algorithm>
#include <cmath>

namespace greenhouse_rail_nav {

int selectRearWall(const std::vector<LineSegment>& lines, double tolerance, double* side) {
  struct Candidate {
    double score = -1.0, side = 1.0, evidence = 0.0, distance = 0.0;
    std::vector<bool> counted;
  };
  std::vector<Candidate> candidates(lines.size());
  int best = -1;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const LineFit2D& wall = lines[i].fit;
    double positive = 0.0, negative = 0.0, pos_dist = 0.0, neg_dist = 0.0;
    std::vector<bool> pos_set(lines.size(), false), neg_set(lines.size(), false);
    for (std::size_t j = 0; j < lines.size(); ++j) {
      if (j == i || !perpendicular(wall, lines[j].fit, tolerance)) continue;
      const LineFit2D& other = lines[j].fit;
      const double along = wall.along(other.centroid);
      if (along < wall.s_min - 0.5 || along > wall.s_max + 0.5) continue;
      const double a = wall.signedDistance(other.centroid + other.direction * other.s_min);
      const double b = wall.signedDistance(other.centroid + other.direction * other.s_max);
      const double centre = std::abs(wall.signedDistance(other.centroid));
      if (std::min(a, b) >= -0.3) {
        positive += other.length();
        pos_dist += other.length() * centre;
        pos_set[j] = true;
      }
      if (std::max(a, b) <= 0.3) {
        negative += other.length();
        neg_dist += other.length() * centre;
        neg_set[j] = true;
      }
    }
    Candidate& c = candidates[i];
    const bool pos = positive >= negative;
    c.side = pos ? 1.0 : -1.0;
    c.evidence = pos ? positive : negative;
    c.distance = c.evidence > 0.0 ? (pos ? pos_dist : neg_dist) / c.evidence : 0.0;
    c.counted = pos ? pos_set : neg_set;
    c.score = wall.length() + c.evidence;
    if (best < 0 || c.score > candidates[static_cast<std::size_t>(best)].score) best = static_cast<int>(i);
  }
  if (best < 0) return best;
  // The other end of the same rows: parallel, facing the best across the lines both count.
  const auto shared = [&](const Candidate& x, const Candidate& y) {
    double common = 0.0;
    for (std::size_t j = 0; j < lines.size(); ++j)
      if (x.counted[j] && y.counted[j]) common += lines[j].fit.length();
    return common;
  };
  int chosen = best;
  const Candidate& b = candidates[static_cast<std::size_t>(best)];
  const LineFit2D& bw = lines[static_cast<std::size_t>(best)].fit;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const Candidate& c = candidates[i];
    if (static_cast<int>(i) == best || c.evidence <= 0.0 || perpendicular(bw, lines[i].fit, tolerance) ||
        angleBetweenLines(bw.direction, lines[i].fit.direction) > tolerance)
      continue;
    const bool facing = b.side * bw.signedDistance(lines[i].fit.centroid) > 0.0 &&
                        c.side * lines[i].fit.signedDistance(bw.centroid) > 0.0;
    const double common = shared(b, c);
    if (!facing || common < 0.8 * b.evidence || common < 0.8 * c.evidence) continue;
    if (c.distance < candidates[static_cast<std::size_t>(chosen)].distance) chosen = static_cast<int>(i);
  }
  *side = candidates[static_cast<std::size_t>(chosen)].side;
  return chosen;
}

double rearWallEnd(const thorvald_map::OccupancyGrid& map, const HeadlandFrame& frame, double u_from, double direction,
                   double max_travel_m, bool* floor_beyond) {
  const double step = 0.5 * map.resolution_m;
  double last = NAN;
  *floor_beyond = false;
  for (double travelled = 0.0; travelled <= max_travel_m; travelled += step) {
    const double u = u_from + direction * travelled;
    bool wall = false;
    for (double v = -0.15; v <= 0.15 && !wall; v += step) wall = map.valueAt(frame.toMap(u, v)) >= 65;
    if (wall) {
      last = u;
    } else if (std::isfinite(last) && travelled - direction * (last - u_from) > 0.3) {
      break;
    }
    if (travelled + step > max_travel_m) return NAN;
  }
  if (!std::isfinite(last)) return NAN;
  int samples = 0, free = 0;
  for (double d = 0.1; d <= 0.3; d += step) {
    for (double v = 0.3; v <= 1.0; v += 0.1) {
      const std::int8_t value = map.valueAt(frame.toMap(last + direction * d, v));
      ++samples;
      free += value >= 0 && value < 25;
    }
  }
  *floor_beyond = 2 * free >= samples;
  return last;
}

}  // namespace greenhouse_rail_nav
