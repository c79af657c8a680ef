#include "cotton_harvester/control/rover_controller.h"

#include <algorithm>
#include <cmath>

namespace cotton_harvester {
namespace control {

std::optional<PositionControl> parsePositionControl(const std::string& name) {
  if (name == "deadband") return PositionControl::kDeadbandAware;
  if (name == "paper_pid") return PositionControl::kPaperPid;
  return std::nullopt;
}

std::string toString(PositionControl control) {
  return control == PositionControl::kDeadbandAware ? "deadband" : "paper_pid";
}

std::string RoverControllerParams::check() const {
  if (const std::string bad = deadband.check(); !bad.empty()) return "deadband " + bad;
  if (!(pid.output_min < 0.0 && pid.output_max > 0.0)) return "pid output range: expected min < 0 < max";
  if (!(pid.kp >= 0.0 && pid.ki >= 0.0 && pid.kd >= 0.0)) return "pid gains: expected >= 0";
  if (const char* bad = swashplate.check(); *bad) return std::string("swashplate ") + bad;
  if (const char* bad = articulation.check(); *bad) return std::string("articulation ") + bad;
  if (!(metres_per_pulse > 0.0)) return "metres_per_pulse: expected > 0 (paper: 0.0018)";
  if (!(position_tolerance_m > 0.0)) return "position_tolerance_m: expected > 0";
  if (!(velocity_lead_limit_m > 0.0)) return "velocity_lead_limit_m: expected > 0";
  if (!(max_speed_mps > 0.0)) return "max_speed_mps: expected > 0";
  if (!(feedforward_effort_per_mps >= 0.0)) return "feedforward_effort_per_mps: expected >= 0";
  if (!(axle_to_joint_m > 0.0)) return "axle_to_joint_m: expected > 0";
  return "";
}

DriveCommand RoverOutput::command() const {
  DriveCommand command;
  command.pwm = static_cast<std::uint8_t>(std::clamp(std::lround(pwm), 0L, 180L));
  command.relay_left = relays.left;
  command.relay_right = relays.right;
  return command;
}

RoverController::RoverController(const RoverControllerParams& params)
    : params_(params), pid_(params.pid), deadband_(params.deadband), articulation_(params.articulation) {}

void RoverController::setPositionTarget(double position_m) {
  if (!std::isfinite(position_m)) return;
  velocity_mode_ = false;
  target_m_ = position_m;
  deadband_.setTarget(position_m);
}

void RoverController::setVelocity(double speed_mps, double yaw_rate_rps) {
  if (!std::isfinite(speed_mps) || !std::isfinite(yaw_rate_rps)) return;
  if (!velocity_mode_) target_m_ = position_m_;
  velocity_mode_ = true;
  speed_mps_ = std::clamp(speed_mps, -params_.max_speed_mps, params_.max_speed_mps);
  deadband_.setVelocity(speed_mps_);
  if (std::abs(speed_mps_) > 1e-3) {
    // Yaw rate of the front half: v tan(γ/2) / l  =>  γ = 2 atan(ω l / v).
    const double angle = 2.0 * std::atan(yaw_rate_rps * params_.axle_to_joint_m / speed_mps_);
    setArticulationTarget(angle * 180.0 / M_PI);
  }
}

void RoverController::holdPosition() {
  if (velocity_mode_) {
    if (params_.position_control == PositionControl::kDeadbandAware) {
      deadband_.stop();
      target_m_ = deadband_.targetM();
    } else {
      target_m_ = position_m_;
    }
  }
  velocity_mode_ = false;
  speed_mps_ = 0.0;
}

void RoverController::setArticulationTarget(double angle_deg) {
  if (!std::isfinite(angle_deg)) return;
  articulation_target_deg_ = std::clamp(angle_deg, -params_.articulation.limit_deg, params_.articulation.limit_deg);
}

bool RoverController::targetReached() const {
  return has_telemetry_ && !velocity_mode_ && std::abs(target_m_ - position_m_) <= params_.position_tolerance_m;
}

RoverOutput RoverController::update(const Telemetry& telemetry, double dt_s) {
  position_m_ = telemetry.encoder_count * params_.metres_per_pulse;
  articulation_deg_ = articulation_.angleFromPot(telemetry.pot_counts);
  if (!has_telemetry_) {
    has_telemetry_ = true;
    target_m_ = position_m_;
    pid_.reset();
    deadband_.reset();
    if (!velocity_mode_) deadband_.setTarget(target_m_);
  }
  if (velocity_mode_ && dt_s > 0.0) {
    target_m_ = std::clamp(target_m_ + speed_mps_ * dt_s, position_m_ - params_.velocity_lead_limit_m,
                           position_m_ + params_.velocity_lead_limit_m);
  }
  RoverOutput output;
  output.relays = articulation_.update(articulation_target_deg_, articulation_deg_, dt_s);
  if (params_.position_control == PositionControl::kDeadbandAware) {
    output.pwm = deadband_.update(position_m_, dt_s);
    output.effort = params_.swashplate.effortFromPwm(output.pwm);
    return output;
  }
  const double setpoint_pulses = target_m_ / params_.metres_per_pulse;
  const double rate_pulses = velocity_mode_ ? speed_mps_ / params_.metres_per_pulse : 0.0;
  const double feedforward = velocity_mode_ ? params_.feedforward_effort_per_mps * speed_mps_ : 0.0;
  output.effort = pid_.update(setpoint_pulses, telemetry.encoder_count, dt_s, rate_pulses, feedforward);
  output.pwm = params_.swashplate.pwmFromEffort(output.effort);
  return output;
}

void ArticulatedOdometry::update(double travel_m, double articulation_deg, double dt_s) {
  if (!std::isfinite(travel_m) || !std::isfinite(articulation_deg)) return;
  const double half = 0.5 * articulation_deg * M_PI / 180.0;
  // The swing over this step, at the mid angle (so that articulating out and back in cancels exactly).
  const double mid = 0.5 * (articulation_deg + last_articulation_deg_) * M_PI / 180.0;
  const double swing = std::isfinite(last_articulation_deg_)
                           ? (articulation_deg - last_articulation_deg_) * M_PI / 180.0 / (1.0 + std::cos(mid))
                           : 0.0;
  last_articulation_deg_ = articulation_deg;
  const double dyaw = travel_m * std::tan(half) / axle_to_joint_m_ + swing;
  x_ += travel_m * std::cos(yaw_ + 0.5 * dyaw);
  y_ += travel_m * std::sin(yaw_ + 0.5 * dyaw);
  yaw_ = std::atan2(std::sin(yaw_ + dyaw), std::cos(yaw_ + dyaw));
  if (dt_s > 0.0) {
    speed_ = travel_m / dt_s;
    yaw_rate_ = dyaw / dt_s;
  }
}

}  // namespace control
}  // namespace cotton_harvester
