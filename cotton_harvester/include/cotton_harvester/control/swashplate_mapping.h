#pragma once

namespace cotton_harvester {
namespace control {

/// Servo PWM values of the swashplate actuator around the hydraulic deadband (paper §2.11, eq. 8).
/// The pump does not move the rover between reverse_max and forward_min (80–98); eq. 8 maps the
/// controller output u in [-100, 100] onto the moving ranges so that the PID never sits in the band.
struct SwashplateMapping {
  double neutral_pwm = 90.0;       ///< swashplate neutral, zero flow (u = 0)
  double forward_min_pwm = 98.0;   ///< upper edge of the deadband (u -> 0+)
  double forward_max_pwm = 108.0;  ///< u = +100
  double reverse_min_pwm = 70.0;   ///< u = -100
  double reverse_max_pwm = 80.0;   ///< lower edge of the deadband (u -> 0-)
  double effort_limit = 100.0;     ///< |u| range of the controller output

  /// Servo PWM for a controller output u (clamped to ±effort_limit); u = 0 gives the neutral.
  /// With the defaults: PWM = 98 + u/10 for u > 0, 80 + u/10 for u < 0 (eq. 8 inverted).
  double pwmFromEffort(double u) const;

  /// eq. 8 as printed: u(x) = 10 (x - 98) for 98 <= x <= 108, 10 (x - 80) for 70 <= x <= 80; the
  /// neutral and the deadband give 0; PWM beyond the ranges saturates at ±effort_limit.
  double effortFromPwm(double pwm) const;

  /// Empty when sound, otherwise which value is wrong and what was expected.
  const char* check() const;
};

}  // namespace control
}  // namespace cotton_harvester
