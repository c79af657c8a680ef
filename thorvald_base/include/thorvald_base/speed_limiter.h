#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "thorvald_base/drive_state.h"
#include "thorvald_base/robot_config.h"
#include "thorvald_base/twist2d.h"

namespace thorvald_base {

/// Limits of the body twist; 0 means no limit on that quantity.
struct TwistLimits {
  double max_linear_mps = 0.0;      ///< |(vx, vy)| [m/s]
  double max_angular_radps = 0.0;   ///< |wz| [rad/s]
  double max_linear_mps2 = 0.0;     ///< change of |(vx, vy)| per second, on each axis [m/s^2]
  double max_angular_radps2 = 0.0;  ///< change of wz per second [rad/s^2]
};

/// Throws ConfigError naming the bad limit (negative or not finite).
void validateTwistLimits(const TwistLimits& limits, const std::string& source);

/// Limits a body twist like diff_drive_controller's speed limiter, but so that the centre of rotation is kept:
/// a velocity limit scales the whole twist by one factor, and an acceleration limit scales the whole step from
/// the previous twist by one factor (so a steady command is approached along its own direction).
class SpeedLimiter {
 public:
  explicit SpeedLimiter(const TwistLimits& limits = {}) : limits_(limits) {}
  void setLimits(const TwistLimits& limits) { limits_ = limits; }
  const TwistLimits& limits() const { return limits_; }

  /// The twist to execute for `target`, `dt_s` [s] after the last executed one (dt <= 0: no acceleration limit).
  Twist2D limit(const Twist2D& target, double dt_s) const;
  /// Records the twist that was executed (after any further scaling), the start of the next acceleration limit.
  void executed(const Twist2D& twist) { previous_ = twist; }
  const Twist2D& previous() const { return previous_; }

 private:
  TwistLimits limits_;
  Twist2D previous_;
};

/// Highest wheel speed a drive can reach [rad/s]: prp_max_rpm (motor) through the gear; 0 when unknown.
double maxWheelSpeed(const DriveConfig& drive);

/// Scales every wheel speed by one common factor so that none exceeds its drive's maximum (steering angles are
/// untouched, so the centre of rotation stays where the command put it). Returns the factor (1 when none is
/// needed, 0..1 otherwise).
double desaturate(const std::vector<DriveConfig>& drives, std::vector<DriveCommand>* commands);

// ---- implementation ----

namespace speed_limiter_detail {

/// Largest k in [0, 1] with |k * value| <= bound (bound 0: no limit).
inline double factorFor(double value, double bound) {
  if (!(bound > 0.0) || std::fabs(value) <= bound) return 1.0;
  return bound / std::fabs(value);
}

}  // namespace speed_limiter_detail

inline void validateTwistLimits(const TwistLimits& l, const std::string& source) {
  const std::pair<const char*, double> values[] = {{"~max_linear_speed", l.max_linear_mps},
                                                   {"~max_angular_speed", l.max_angular_radps},
                                                   {"~max_linear_acceleration", l.max_linear_mps2},
                                                   {"~max_angular_acceleration", l.max_angular_radps2}};
  for (const auto& v : values) {
    if (!std::isfinite(v.second) || v.second < 0.0) {
      throw ConfigError(source, v.first, "must be finite and >= 0 (0: no limit), found " + std::to_string(v.second));
    }
  }
}

inline Twist2D SpeedLimiter::limit(const Twist2D& target, double dt_s) const {
  const double speed = std::hypot(target.vx, target.vy);
  const double k = std::min(speed_limiter_detail::factorFor(speed, limits_.max_linear_mps),
                            speed_limiter_detail::factorFor(target.wz, limits_.max_angular_radps));
  Twist2D out{k * target.vx, k * target.vy, k * target.wz};
  if (dt_s > 0.0) {
    const Twist2D step{out.vx - previous_.vx, out.vy - previous_.vy, out.wz - previous_.wz};
    const double lin = limits_.max_linear_mps2 * dt_s, ang = limits_.max_angular_radps2 * dt_s;
    const double a =
        std::min({speed_limiter_detail::factorFor(step.vx, lin), speed_limiter_detail::factorFor(step.vy, lin),
                  speed_limiter_detail::factorFor(step.wz, ang)});
    out = {previous_.vx + a * step.vx, previous_.vy + a * step.vy, previous_.wz + a * step.wz};
  }
  return out;
}

inline double maxWheelSpeed(const DriveConfig& d) {
  if (!(d.prp_max_rpm > 0.0) || !(d.prp_gr_rt > 0.0)) return 0.0;
  return d.prp_max_rpm / d.prp_gr_rt * M_PI / 30.0;
}

inline double desaturate(const std::vector<DriveConfig>& drives, std::vector<DriveCommand>* commands) {
  double k = 1.0;
  for (size_t i = 0; i < drives.size() && i < commands->size(); ++i) {
    k = std::min(k, speed_limiter_detail::factorFor((*commands)[i].wheel_speed_radps, maxWheelSpeed(drives[i])));
  }
  if (k < 1.0) {
    for (auto& c : *commands) c.wheel_speed_radps *= k;
  }
  return k;
}

}  // namespace thorvald_base
