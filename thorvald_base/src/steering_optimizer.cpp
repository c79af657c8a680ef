#include "thorvald_base/steering_optimizer.h"

#include <algorithm>
#include <cmath>

#include "thorvald_base/angles.h"

namespace thorvald_base {

SteeringChoice chooseSteering(double wanted_rad, double current_rad, double limit_rad) {
  const double direct = normalizeAngle(wanted_rad);
  const double twin = normalizeAngle(wanted_rad + kPi);
  const bool direct_ok = std::fabs(direct) <= limit_rad;
  const bool twin_ok = std::fabs(twin) <= limit_rad;
  if (direct_ok && twin_ok) {
    // Steering travel is the plain difference: the cable does not let the module wrap through +-pi.
    const bool use_twin = std::fabs(twin - current_rad) < std::fabs(direct - current_rad);
    return {use_twin ? twin : direct, use_twin ? -1.0 : 1.0, 1.0};
  }
  if (direct_ok) return {direct, 1.0, 1.0};
  if (twin_ok) return {twin, -1.0, 1.0};
  // Neither fits (limit below 90 deg): the limit nearest the wanted direction, rolling along the part that fits.
  const double direct_clamped = std::clamp(direct, -limit_rad, limit_rad);
  const double twin_clamped = std::clamp(twin, -limit_rad, limit_rad);
  const double direct_miss = std::fabs(angleDiff(direct, direct_clamped));
  const double twin_miss = std::fabs(angleDiff(twin, twin_clamped));
  if (twin_miss < direct_miss) return {twin_clamped, -1.0, std::max(0.0, std::cos(twin_miss))};
  return {direct_clamped, 1.0, std::max(0.0, std::cos(direct_miss))};
}

double alignmentScale(double max_steering_error_rad, double aligned_rad, double stopped_rad) {
  const double e = std::fabs(max_steering_error_rad);
  if (e <= aligned_rad) return 1.0;
  if (e >= stopped_rad || stopped_rad <= aligned_rad) return 0.0;
  return (stopped_rad - e) / (stopped_rad - aligned_rad);
}

}  // namespace thorvald_base
