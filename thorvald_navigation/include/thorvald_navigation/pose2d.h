#pragma once

#include <cmath>

#include <Eigen/Core>

namespace thorvald_navigation {

constexpr double kPi = 3.14159265358979323846;

/// Wraps an angle into [-pi, pi) [rad].
inline double normalizeAngle(double angle_rad) {
  double a = std::fmod(angle_rad + kPi, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  return a - kPi;
}

/// A planar pose: position [m] and heading [rad] of a frame in its parent frame.
struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;

  bool finite() const { return std::isfinite(x) && std::isfinite(y) && std::isfinite(yaw); }

  /// This pose followed by `b` (b expressed in this pose's frame).
  Pose2D operator*(const Pose2D& b) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {x + c * b.x - s * b.y, y + s * b.x + c * b.y, normalizeAngle(yaw + b.yaw)};
  }
  Pose2D inverse() const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {-c * x - s * y, s * x - c * y, normalizeAngle(-yaw)};
  }
  /// A point given in this pose's frame, expressed in the parent frame.
  Eigen::Vector2d transform(const Eigen::Vector2d& p) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
  }
};

}  // namespace thorvald_navigation
