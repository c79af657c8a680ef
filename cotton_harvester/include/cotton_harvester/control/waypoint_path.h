#pragma once

#include <Eigen/Core>
#include <vector>

namespace cotton_harvester {
namespace control {

/// A planar pose in the world frame: position [m] and heading [rad] (counter-clockwise from +x).
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

/// Where a point lies against a path: the closest point's arc length, the point, and the signed distance.
struct PathProjection {
  double s_m = 0.0;                                 ///< arc length of the closest point along the path [m]
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  ///< the closest point [m]
  double cross_track_m = 0.0;                       ///< distance to the path, positive left of it [m]
};

/// A path of waypoints in the world frame (the rows' ends a user records with the GNSS, or a planned turn) as a
/// polyline parametrised by arc length. Beyond its ends the path continues straight along its first and last
/// segments, so a follower aiming past the end keeps the last heading.
class WaypointPath {
 public:
  WaypointPath() = default;
  /// At least two waypoints; consecutive duplicates are dropped. Throws std::invalid_argument when fewer than two
  /// distinct finite waypoints remain.
  explicit WaypointPath(const std::vector<Eigen::Vector2d>& waypoints);

  double lengthM() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }
  const std::vector<Eigen::Vector2d>& waypoints() const { return points_; }
  bool empty() const { return points_.size() < 2; }

  /// Point at arc length s [m]; extrapolated straight beyond both ends.
  Eigen::Vector2d pointAt(double s_m) const;
  /// Heading of the path at arc length s [rad] (of the segment holding s).
  double headingAt(double s_m) const;
  /// Closest point among arc lengths [s_from, s_to] (clamped to the path).
  PathProjection project(const Eigen::Vector2d& p, double s_from_m, double s_to_m) const;
  /// Closest point over the whole path.
  PathProjection project(const Eigen::Vector2d& p) const { return project(p, 0.0, lengthM()); }

 private:
  std::size_t segmentAt(double s_m) const;

  std::vector<Eigen::Vector2d> points_;
  std::vector<double> cumulative_;  ///< arc length at each waypoint [m]
};

/// Angle wrapped into (-pi, pi] [rad].
double wrapAngle(double angle_rad);

}  // namespace control
}  // namespace cotton_harvester
