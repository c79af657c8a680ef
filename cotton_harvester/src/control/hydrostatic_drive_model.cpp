#include "cotton_harvester/control/hydrostatic_drive_model.h"

#include <algorithm>
#include <cmath>

namespace cotton_harvester {
namespace control {

const char* HydrostaticDriveParams::check() const {
  if (!(pwm_min < deadband_low_pwm && deadband_low_pwm <= deadband_high_pwm && deadband_high_pwm < pwm_max))
    return "pwm ranges: expected pwm_min < deadband_low_pwm <= deadband_high_pwm < pwm_max";
  if (!(max_forward_speed_mps > 0.0 && max_reverse_speed_mps > 0.0)) return "max speeds: expected > 0";
  if (!(actuator_rate_pwm_per_s > 0.0)) return "actuator_rate_pwm_per_s: expected > 0";
  if (!(flow_time_constant_s >= 0.0)) return "flow_time_constant_s: expected >= 0";
  if (!(metres_per_pulse > 0.0)) return "metres_per_pulse: expected > 0";
  if (!(articulation_rate_deg_per_s > 0.0 && articulation_limit_deg > 0.0)) return "articulation: expected > 0";
  if (!(axle_to_joint_m > 0.0)) return "axle_to_joint_m: expected > 0";
  return "";
}

HydrostaticDriveModel::HydrostaticDriveModel(const HydrostaticDriveParams& params)
    : params_(params), actuator_pwm_(params.neutral_pwm) {}

double HydrostaticDriveModel::flowSpeed(double pwm) const {
  if (pwm > params_.deadband_high_pwm) {
    return params_.max_forward_speed_mps * (std::min(pwm, params_.pwm_max) - params_.deadband_high_pwm) /
           (params_.pwm_max - params_.deadband_high_pwm);
  }
  if (pwm < params_.deadband_low_pwm) {
    return -params_.max_reverse_speed_mps * (params_.deadband_low_pwm - std::max(pwm, params_.pwm_min)) /
           (params_.deadband_low_pwm - params_.pwm_min);
  }
  return 0.0;
}

void HydrostaticDriveModel::step(double pwm_command, bool relay_left, bool relay_right, double dt_s) {
  if (!(dt_s > 0.0)) return;
  const double command =
      std::isfinite(pwm_command) ? std::clamp(pwm_command, params_.pwm_min, params_.pwm_max) : actuator_pwm_;
  const double max_change = params_.actuator_rate_pwm_per_s * dt_s;
  actuator_pwm_ += std::clamp(command - actuator_pwm_, -max_change, max_change);

  const double target_speed = flowSpeed(actuator_pwm_);
  if (params_.flow_time_constant_s > 0.0) {
    speed_mps_ += (target_speed - speed_mps_) * (1.0 - std::exp(-dt_s / params_.flow_time_constant_s));
  } else {
    speed_mps_ = target_speed;
  }
  position_m_ += speed_mps_ * dt_s;

  const double turn = (relay_left ? 1.0 : 0.0) - (relay_right ? 1.0 : 0.0);
  articulation_deg_ = std::clamp(articulation_deg_ + turn * params_.articulation_rate_deg_per_s * dt_s,
                                 -params_.articulation_limit_deg, params_.articulation_limit_deg);
}

std::int32_t HydrostaticDriveModel::encoderCount() const {
  return static_cast<std::int32_t>(std::floor(position_m_ / params_.metres_per_pulse));
}

}  // namespace control
}  // namespace cotton_harvester
