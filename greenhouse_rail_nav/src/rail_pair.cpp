#include "greenhouse_rail_nav/rail_pair.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace greenhouse_rail_nav {

RailLine makeRailLine(const std::vector<Eigen::Vector2d>& points, double max_gap_m, std::size_t min_run) {
  RailLine rail;
  rail.fit = fitLine(points);
  rail.points = points.size();
  if (rail.fit.direction.x() < 0.0) rail.fit.flip();
  if (points.empty()) return rail;
  std::vector<double> along;
  along.reserve(points.size());
  for (const auto& p : points) along.push_back(rail.fit.along(p));
  std::sort(along.begin(), along.end());
  // The first point from which min_run points follow with no gap above max_gap_m: a stray point or two in
  // front of the rail is skipped, but the start is not moved into the rail by a share of its length.
  rail.near_end = along.front();
  const std::size_t run = std::max<std::size_t>(1, min_run);
  for (std::size_t i = 0; i + run <= along.size(); ++i) {
    bool continuous = true;
    for (std::size_t j = i + 1; j < i + run && continuous; ++j) continuous = along[j] - along[j - 1] <= max_gap_m;
    if (continuous) {
      rail.near_end = along[i];
      break;
    }
  }
  return rail;
}

RailLine trimRailLine(const std::vector<Eigen::Vector2d>& points, const RailLine& rail, double trim_m) {
  RailLine current = rail;
  for (const double distance : {trim_m, 0.5 * trim_m}) {
    std::vector<Eigen::Vector2d> close;
    for (const auto& p : points)
      if (std::abs(current.fit.signedDistance(p)) <= distance) close.push_back(p);
    if (close.size() < 3) break;
    current = makeRailLine(close);
  }
  current.fit.linearity = rail.fit.linearity;
  return current;
}

double lineCoverage(const std::vector<Eigen::Vector2d>& points, const LineFit2D& line, double bin_m) {
  if (points.empty() || !(bin_m > 0.0)) return 0.0;
  double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
  for (const auto& p : points) {
    lo = std::min(lo, line.along(p));
    hi = std::max(hi, line.along(p));
  }
  const std::size_t bins = static_cast<std::size_t>(std::floor((hi - lo) / bin_m)) + 1;
  std::vector<bool> filled(bins, false);
  for (const auto& p : points)
    filled[std::min(bins - 1, static_cast<std::size_t>((line.along(p) - lo) / bin_m))] = true;
  return static_cast<double>(std::count(filled.begin(), filled.end(), true)) / static_cast<double>(bins);
}

RailPair makeRailPair(const RailLine& a, const RailLine& b) {
  RailPair pair{a, b, {}, 0.0};
  Eigen::Vector2d db = b.fit.direction;
  if (db.dot(a.fit.direction) < 0.0) db = -db;
  const Eigen::Vector2d d =
      (a.fit.direction * static_cast<double>(a.points) + db * static_cast<double>(b.points)).normalized();
  // Any point half-way between points of the two lines lies on the centre line.
  const Eigen::Vector2d centre = 0.5 * (a.fit.centroid + b.fit.centroid);
  const Eigen::Vector2d normal(-d.y(), d.x());
  pair.gauge_m = std::abs(normal.dot(b.fit.centroid - a.fit.centroid));
  // Near ends of each rail, expressed along d from the centre point.
  const double start_a = d.dot(a.fit.centroid + a.near_end * a.fit.direction - centre);
  const double start_b = d.dot(b.fit.centroid + b.near_end * b.fit.direction - centre);
  // The nearer of the two starts: occlusion (a dropout, a leaf) can only make a rail look shorter.
  const Eigen::Vector2d origin = centre + std::min(start_a, start_b) * d;
  pair.rail_in_base = thorvald_base::Pose2D(origin.x(), origin.y(), std::atan2(d.y(), d.x()));
  return pair;
}

}  // namespace greenhouse_rail_nav
