#pragma once

#include <cmath>

#include <Eigen/Core>

namespace greenhouse_rail_nav {

/// Wraps an angle to (-pi, pi] [rad].
inline double normalizeAngle(double angle_rad) {
  double a = std::fmod(angle_rad + M_PI, 2.0 * M_PI);
  if (a <= 0.0) a += 2.0 * M_PI;
  return a - M_PI;
}

/// A planar rigid transform / pose: position [m] and heading [rad]. As a transform, `a.compose(b)`
/// maps points of frame b into the frame a is expressed in (a * b).
struct Pose2D {
  double x = 0.0;    ///< [m]
  double y = 0.0;    ///< [m]
  double yaw = 0.0;  ///< [rad]

  Pose2D() = default;
  Pose2D(double x_m, double y_m, double yaw_rad) : x(x_m), y(y_m), yaw(yaw_rad) {}

  /// Maps a point given in this pose's frame into the parent frame [m].
  Eigen::Vector2d transformPoint(const Eigen::Vector2d& p) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
  }
  /// this * other.
  Pose2D compose(const Pose2D& other) const {
    const Eigen::Vector2d p = transformPoint({other.x, other.y});
    return {p.x(), p.y(), normalizeAngle(yaw + other.yaw)};
  }
  /// The inverse transform.
  Pose2D inverse() const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {-(c * x + s * y), -(-s * x + c * y), normalizeAngle(-yaw)};
  }
  Eigen::Vector2d position() const { return {x, y}; }
  /// Unit vector along the pose's x axis.
  Eigen::Vector2d heading() const { return {std::cos(yaw), std::sin(yaw)}; }
};

}  // namespace greenhouse_rail_nav
