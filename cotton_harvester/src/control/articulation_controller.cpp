#include "cotton_harvester/control/articulation_controller.h"

#include <algorithm>
#include <cmath>

namespace cotton_harvester {
namespace control {

const char* ArticulationParams::check() const {
  if (!(pot_counts_per_deg != 0.0 && std::isfinite(pot_counts_per_deg))) return "pot_counts_per_deg: expected != 0";
  if (!(limit_deg > 0.0 && limit_deg <= 90.0)) return "limit_deg: expected in (0, 90]";
  if (!(kp > 0.0)) return "kp: expected > 0";
  if (!(deadband_deg >= 0.0)) return "deadband_deg: expected >= 0";
  if (!(full_duty_deg > deadband_deg)) return "full_duty_deg: expected > deadband_deg";
  if (!(relay_period_s > 0.0)) return "relay_period_s: expected > 0";
  return "";
}

double ArticulationController::angleFromPot(double counts) const {
  return (counts - params_.pot_center_counts) / params_.pot_counts_per_deg;
}

double ArticulationController::potFromAngle(double angle_deg) const {
  return params_.pot_center_counts + angle_deg * params_.pot_counts_per_deg;
}

RelayCommand ArticulationController::update(double target_deg, double measured_deg, double dt_s) {
  RelayCommand command;
  if (!std::isfinite(target_deg) || !std::isfinite(measured_deg) || !(dt_s > 0.0)) return command;
  const double target = std::clamp(target_deg, -params_.limit_deg, params_.limit_deg);
  const double output = params_.kp * (target - measured_deg);
  phase_s_ = std::fmod(phase_s_ + dt_s, params_.relay_period_s);
  const double magnitude = std::abs(output);
  if (magnitude < params_.deadband_deg) return command;
  const double duty = std::min(1.0, magnitude / params_.full_duty_deg);
  if (phase_s_ >= duty * params_.relay_period_s && duty < 1.0) return command;
  // Never drive further out past the limit.
  if (output > 0.0 && measured_deg < params_.limit_deg) command.left = true;
  if (output < 0.0 && measured_deg > -params_.limit_deg) command.right = true;
  return command;
}

}  // namespace control
}  // namespace cotton_harvester
