#pragma once

#include <cmath>

#include <Eigen/Core>

#include "thorvald_base/angles.h"

namespace thorvald_base {

/// A planar pose, or the rigid transform it stands for: the position [m] and heading [rad] of a frame in its parent
/// frame (base_link in odom, odom in map, a rail frame in the map, the origin of a grid). `a * b` is b expressed in
/// a's parent frame; headings of composed and inverted poses are normalised by normalizeAngle ([-pi, pi)).
struct Pose2D {
  double x = 0.0;    ///< [m]
  double y = 0.0;    ///< [m]
  double yaw = 0.0;  ///< [rad]

  constexpr Pose2D() = default;
  constexpr Pose2D(double x_m, double y_m, double yaw_rad) : x(x_m), y(y_m), yaw(yaw_rad) {}

  bool finite() const { return std::isfinite(x) && std::isfinite(y) && std::isfinite(yaw); }

  /// A point given in this pose's frame, expressed in the parent frame [m].
  Eigen::Vector2d transformPoint(const Eigen::Vector2d& p) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
  }
  /// This pose followed by `b` (b given in this pose's frame).
  Pose2D operator*(const Pose2D& b) const {
    const Eigen::Vector2d p = transformPoint({b.x, b.y});
    return {p.x(), p.y(), normalizeAngle(yaw + b.yaw)};
  }
  /// The inverse transform: the parent frame expressed in this pose's frame.
  Pose2D inverse() const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {-c * x - s * y, s * x - c * y, normalizeAngle(-yaw)};
  }
  /// Position [m].
  Eigen::Vector2d position() const { return {x, y}; }
  /// Unit vector along the pose's x axis.
  Eigen::Vector2d heading() const { return {std::cos(yaw), std::sin(yaw)}; }
};

}  // namespace thorvald_base
