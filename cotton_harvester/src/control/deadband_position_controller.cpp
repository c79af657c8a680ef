#include "cotton_harvester/control/deadband_position_controller.h"

#include <algorithm>
#include <cmath>

namespace cotton_harvester {
namespace control {

std::string DeadbandControllerParams::check() const {
  if (!(pwm_min < reverse_edge_pwm && reverse_edge_pwm <= neutral_pwm && neutral_pwm <= forward_edge_pwm &&
        forward_edge_pwm < pwm_max))
    return "pwm: expected pwm_min < reverse_edge_pwm <= neutral_pwm <= forward_edge_pwm < pwm_max";
  if (!(forward_mps_per_pwm > 0.0 && reverse_mps_per_pwm > 0.0)) return "mps_per_pwm: expected > 0";
  if (!(max_speed_mps > 0.0 && max_accel_mps2 > 0.0)) return "max_speed_mps, max_accel_mps2: expected > 0";
  if (!(position_gain > 0.0 && integral_gain >= 0.0 && integral_limit_mps >= 0.0))
    return "position_gain > 0, integral_gain >= 0, integral_limit_mps >= 0 expected";
  if (!(speed_filter_s >= 0.0 && flow_lag_s >= 0.0)) return "speed_filter_s, flow_lag_s: expected >= 0";
  if (!(actuator_rate_pwm_per_s > 0.0)) return "actuator_rate_pwm_per_s: expected > 0";
  if (!(edge_learning_pwm_per_s >= 0.0 && max_edge_correction_pwm >= 0.0))
    return "edge_learning_pwm_per_s, max_edge_correction_pwm: expected >= 0";
  if (!(stop_tolerance_m > 0.0 && restart_tolerance_m >= stop_tolerance_m))
    return "tolerances: expected 0 < stop_tolerance_m <= restart_tolerance_m";
  return "";
}

DeadbandPositionController::DeadbandPositionController(const DeadbandControllerParams& params) : params_(params) {}

void DeadbandPositionController::setTarget(double target_m) {
  if (!std::isfinite(target_m)) return;
  velocity_mode_ = false;
  if (target_m != target_m_) at_rest_ = false;
  target_m_ = target_m;
}

void DeadbandPositionController::setVelocity(double speed_mps) {
  if (!std::isfinite(speed_mps)) return;
  if (!velocity_mode_) target_m_ = reference_m_;
  velocity_mode_ = true;
  at_rest_ = false;
  velocity_mps_ = std::clamp(speed_mps, -params_.max_speed_mps, params_.max_speed_mps);
}

void DeadbandPositionController::stop() {
  if (!velocity_mode_) return;
  velocity_mode_ = false;
  at_rest_ = false;
  const double braking_m = reference_mps_ * std::abs(reference_mps_) / (2.0 * params_.max_accel_mps2);
  target_m_ = reference_m_ + braking_m;
}

void DeadbandPositionController::reset() {
  initialised_ = false;
  integral_mps_ = 0.0;
}

double DeadbandPositionController::pwmForSpeed(double speed_mps) const {
  if (!(std::abs(speed_mps) > 0.0)) return params_.neutral_pwm;
  if (speed_mps > 0.0)
    return std::min(params_.pwm_max,
                    params_.forward_edge_pwm + forward_correction_pwm_ + speed_mps / params_.forward_mps_per_pwm);
  return std::max(params_.pwm_min,
                  params_.reverse_edge_pwm - reverse_correction_pwm_ + speed_mps / params_.reverse_mps_per_pwm);
}

void DeadbandPositionController::advanceProfile(double dt_s) {
  if (velocity_mode_) target_m_ += velocity_mps_ * dt_s;
  const double remaining = target_m_ - reference_m_;
  const double direction = remaining >= 0.0 ? 1.0 : -1.0;
  // The fastest speed from which the profile can still stop at the target, capped by the cruise speed (in
  // velocity mode: the commanded speed).
  const double cruise = velocity_mode_ ? std::abs(velocity_mps_) : params_.max_speed_mps;
  const double stopping = std::sqrt(2.0 * params_.max_accel_mps2 * std::abs(remaining));
  const double wanted = velocity_mode_ ? velocity_mps_ : direction * std::min(cruise, stopping);
  const double step = params_.max_accel_mps2 * dt_s;
  reference_mps_ += std::clamp(wanted - reference_mps_, -step, step);
  const double next = reference_m_ + reference_mps_ * dt_s;
  if (!velocity_mode_ && (next - target_m_) * direction >= 0.0) {
    reference_m_ = target_m_;
    reference_mps_ = 0.0;
  } else {
    reference_m_ = next;
  }
}

double DeadbandPositionController::update(double position_m, double dt_s) {
  if (!std::isfinite(position_m) || !(dt_s > 0.0) || !std::isfinite(dt_s)) return params_.neutral_pwm;
  if (!initialised_) {
    initialised_ = true;
    last_position_m_ = position_m;
    reference_m_ = position_m;
    reference_mps_ = 0.0;
    speed_mps_ = 0.0;
    actuator_pwm_ = params_.neutral_pwm;
    if (!velocity_mode_ && at_rest_) target_m_ = position_m;
  }
  const double raw_speed = (position_m - last_position_m_) / dt_s;
  last_position_m_ = position_m;
  const double alpha = params_.speed_filter_s > 0.0 ? 1.0 - std::exp(-dt_s / params_.speed_filter_s) : 1.0;
  speed_mps_ += alpha * (raw_speed - speed_mps_);

  const double error_to_target = target_m_ - position_m;
  if (at_rest_ && !velocity_mode_) {
    if (std::abs(error_to_target) <= params_.restart_tolerance_m) return send(params_.neutral_pwm, dt_s);
    at_rest_ = false;  // pushed away or a new target: move again, the profile from here
    reference_m_ = position_m;
    reference_mps_ = speed_mps_;
  }
  // The profile waits while the actuator is still inside the deadband and the rover has not started: the dead
  // time of crossing the band would otherwise turn into a lag the feedback then overcorrects.
  const bool in_band = actuator_pwm_ > params_.reverse_edge_pwm && actuator_pwm_ < params_.forward_edge_pwm;
  const bool waiting = !velocity_mode_ && in_band && std::abs(speed_mps_) < 0.01 && std::abs(reference_mps_) < 1e-9 &&
                       std::abs(error_to_target) > params_.stop_tolerance_m;
  if (waiting) {
    // Drive the actuator out of the band towards the first speed of the profile.
    reference_m_ = position_m;
    const double first_mps = params_.max_accel_mps2 * params_.flow_lag_s;
    return send(pwmForSpeed(error_to_target > 0.0 ? first_mps : -first_mps), dt_s);
  }
  const double previous_reference_mps = reference_mps_;
  advanceProfile(dt_s);
  const double reference_accel = (reference_mps_ - previous_reference_mps) / dt_s;

  // Stop early: once the profile has arrived, the swashplate returns to neutral when the rover would coast the
  // rest of the way (the actuator's travel back to the edge at a falling speed, then the hydraulic lag).
  const bool profile_done = !velocity_mode_ && reference_m_ == target_m_ && reference_mps_ == 0.0;
  const double edge = speed_mps_ >= 0.0 ? params_.forward_edge_pwm : params_.reverse_edge_pwm;
  const double to_edge_s = std::abs(actuator_pwm_ - edge) / params_.actuator_rate_pwm_per_s;
  // The pump's flow follows the actuator (known from the commands sent) and the wheels lag the flow: after neutral
  // is sent the flow falls to zero at the edge (on average half the present flow until then) and the wheels' speed
  // then decays with the lag; the measured speed also trails the true one by the speed filter.
  const double flow_mps =
      actuator_pwm_ >= params_.forward_edge_pwm + forward_correction_pwm_
          ? (actuator_pwm_ - params_.forward_edge_pwm - forward_correction_pwm_) * params_.forward_mps_per_pwm
      : actuator_pwm_ <= params_.reverse_edge_pwm - reverse_correction_pwm_
          ? (actuator_pwm_ - params_.reverse_edge_pwm + reverse_correction_pwm_) * params_.reverse_mps_per_pwm
          : 0.0;
  const double coast_m = 0.5 * flow_mps * to_edge_s + speed_mps_ * (params_.flow_lag_s + params_.speed_filter_s);
  const double direction = error_to_target >= 0.0 ? 1.0 : -1.0;
  // Also before the profile has arrived: once the rover would coast to the target with the swashplate at
  // neutral, it goes to neutral (on a short step the profile's braking comes too late for the slow actuator).
  const bool coasts_there =
      !velocity_mode_ && speed_mps_ * direction > 0.0 && (error_to_target - coast_m) * direction <= 0.0;
  if ((profile_done && std::abs(error_to_target) <= params_.stop_tolerance_m) || coasts_there ||
      (profile_done && (error_to_target - coast_m) * direction <= 0.0)) {
    at_rest_ = true;
    integral_mps_ = 0.0;
    return send(params_.neutral_pwm, dt_s);
  }

  const double error = reference_m_ - position_m;
  const double limit = params_.max_speed_mps * 1.2;
  // Feedforward one flow lag ahead on the profile: the lagging speed then meets the profile.
  const double lead_mps = reference_mps_ + reference_accel * params_.flow_lag_s;
  const double unsaturated = lead_mps + params_.position_gain * error + integral_mps_;
  // Anti-windup: integrate only while the command is not saturated in the direction of the error.
  if (!(std::abs(unsaturated) >= limit && unsaturated * error > 0.0))
    integral_mps_ = std::clamp(integral_mps_ + params_.integral_gain * error * dt_s, -params_.integral_limit_mps,
                               params_.integral_limit_mps);
  const double command = std::clamp(lead_mps + params_.position_gain * error + integral_mps_, -limit, limit);
  return send(pwmForSpeed(command), dt_s);
}

double DeadbandPositionController::send(double pwm, double dt_s) {
  // Edge learning: the actuator sits at a command past an edge and the rover stands still.
  const bool settled = std::abs(actuator_pwm_ - pwm) < 0.5;
  if (settled && std::abs(speed_mps_) < 0.005) {
    const double step = params_.edge_learning_pwm_per_s * dt_s;
    if (pwm > params_.forward_edge_pwm)
      forward_correction_pwm_ = std::min(params_.max_edge_correction_pwm, forward_correction_pwm_ + step);
    else if (pwm < params_.reverse_edge_pwm)
      reverse_correction_pwm_ = std::min(params_.max_edge_correction_pwm, reverse_correction_pwm_ + step);
  }
  // The actuator cannot follow faster than its slew: the command the model tracks is what it will reach.
  const double step = params_.actuator_rate_pwm_per_s * dt_s;
  actuator_pwm_ += std::clamp(pwm - actuator_pwm_, -step, step);
  return pwm;
}

}  // namespace control
}  // namespace cotton_harvester
