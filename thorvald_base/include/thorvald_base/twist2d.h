#pragma once

#include <cmath>

namespace thorvald_base {

/// A planar velocity of base_link expressed in base_link: [m/s], [m/s], [rad/s].
struct Twist2D {
  double vx = 0.0;
  double vy = 0.0;
  double wz = 0.0;

  bool finite() const { return std::isfinite(vx) && std::isfinite(vy) && std::isfinite(wz); }
  bool isZero(double eps = 1e-9) const { return std::fabs(vx) < eps && std::fabs(vy) < eps && std::fabs(wz) < eps; }
};

}  // namespace thorvald_base
