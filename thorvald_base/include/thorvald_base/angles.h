#pragma once

#include <cmath>

namespace thorvald_base {

constexpr double kPi = 3.14159265358979323846;

/// Wraps an angle into [-pi, pi) [rad]. The one place angles are normalised.
inline double normalizeAngle(double angle_rad) {
  double a = std::fmod(angle_rad + kPi, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  return a - kPi;
}

/// Signed shortest difference a - b, in [-pi, pi) [rad].
inline double angleDiff(double a_rad, double b_rad) { return normalizeAngle(a_rad - b_rad); }

}  // namespace thorvald_base
