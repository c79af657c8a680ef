#include "cotton_harvester/control/swashplate_mapping.h"

#include <algorithm>
#include <cmath>

namespace cotton_harvester {
namespace control {

double SwashplateMapping::pwmFromEffort(double u) const {
  if (!std::isfinite(u) || u == 0.0) return neutral_pwm;
  const double clamped = std::clamp(u, -effort_limit, effort_limit);
  if (clamped > 0.0) return forward_min_pwm + (forward_max_pwm - forward_min_pwm) * clamped / effort_limit;
  return reverse_max_pwm + (reverse_max_pwm - reverse_min_pwm) * clamped / effort_limit;
}

double SwashplateMapping::effortFromPwm(double pwm) const {
  if (!std::isfinite(pwm)) return 0.0;
  if (pwm >= forward_min_pwm) {
    return std::min(effort_limit, effort_limit * (pwm - forward_min_pwm) / (forward_max_pwm - forward_min_pwm));
  }
  if (pwm <= reverse_max_pwm) {
    return std::max(-effort_limit, effort_limit * (pwm - reverse_max_pwm) / (reverse_max_pwm - reverse_min_pwm));
  }
  return 0.0;  // deadband and neutral
}

const char* SwashplateMapping::check() const {
  if (!(effort_limit > 0.0)) return "effort_limit: expected > 0";
  if (!(reverse_min_pwm < reverse_max_pwm)) return "reverse_min_pwm: expected < reverse_max_pwm";
  if (!(reverse_max_pwm <= neutral_pwm)) return "reverse_max_pwm: expected <= neutral_pwm";
  if (!(neutral_pwm <= forward_min_pwm)) return "forward_min_pwm: expected >= neutral_pwm";
  if (!(forward_min_pwm < forward_max_pwm)) return "forward_max_pwm: expected > forward_min_pwm";
  if (!(reverse_min_pwm >= 0.0 && forward_max_pwm <= 180.0)) return "pwm range: expected within servo 0..180";
  return "";
}

}  // namespace control
}  // namespace cotton_harvester
