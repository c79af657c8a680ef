#include "cotton_harvester/control/waypoint_path.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cotton_harvester {
namespace control {

double wrapAngle(double angle_rad) { return std::atan2(std::sin(angle_rad), std::cos(angle_rad)); }

WaypointPath::WaypointPath(const std::vector<Eigen::Vector2d>& waypoints) {
  for (const Eigen::Vector2d& p : waypoints) {
    if (!p.allFinite()) throw std::invalid_argument("waypoint path: a waypoint is not finite");
    if (!points_.empty() && (p - points_.back()).norm() < 1e-9) continue;
    cumulative_.push_back(points_.empty() ? 0.0 : cumulative_.back() + (p - points_.back()).norm());
    points_.push_back(p);
  }
  if (points_.size() < 2)
    throw std::invalid_argument("waypoint path: expected at least two distinct waypoints, got " +
                                std::to_string(points_.size()));
}

std::size_t WaypointPath::segmentAt(double s_m) const {
  const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), s_m);
  const std::ptrdiff_t i = (it - cumulative_.begin()) - 1;
  return static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(i, 0, static_cast<std::ptrdiff_t>(points_.size()) - 2));
}

Eigen::Vector2d WaypointPath::pointAt(double s_m) const {
  const std::size_t i = segmentAt(s_m);
  const Eigen::Vector2d d = points_[i + 1] - points_[i];
  return points_[i] + d.normalized() * (s_m - cumulative_[i]);
}

double WaypointPath::headingAt(double s_m) const {
  const std::size_t i = segmentAt(s_m);
  const Eigen::Vector2d d = points_[i + 1] - points_[i];
  return std::atan2(d.y(), d.x());
}

PathProjection WaypointPath::project(const Eigen::Vector2d& p, double s_from_m, double s_to_m) const {
  const double from = std::clamp(s_from_m, 0.0, lengthM());
  const double to = std::clamp(s_to_m, from, lengthM());
  PathProjection best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = segmentAt(from); i + 1 < points_.size() && cumulative_[i] <= to; ++i) {
    const Eigen::Vector2d a = points_[i], d = points_[i + 1] - points_[i];
    const double len = cumulative_[i + 1] - cumulative_[i];
    const double lo = std::max(0.0, from - cumulative_[i]), hi = std::min(len, to - cumulative_[i]);
    const double t = std::clamp((p - a).dot(d) / len, lo, hi);
    const Eigen::Vector2d q = a + d / len * t;
    const double d2 = (p - q).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best.s_m = cumulative_[i] + t;
      best.point = q;
      const double cross = d.x() * (p - q).y() - d.y() * (p - q).x();
      best.cross_track_m = std::copysign(std::sqrt(d2), cross == 0.0 ? 1.0 : cross);
    }
  }
  return best;
}

}  // namespace control
}  // namespace cotton_harvester
