#pragma once

// Loaders of the parameter structs the control nodes share (same keys in every node).

#include "cotton_harvester/control/manipulator_calibration.h"
#include "cotton_harvester/control/rover_controller.h"
#include "node_params.h"

namespace cotton_harvester {
namespace control {

/// Manipulator calibration under `nh` (keys as the struct's members).
inline ManipulatorCalibration loadCalibration(const NodeParams& nh) {
  ManipulatorCalibration c;
  c.vertical_slope_steps_per_m = readDouble(nh, "vertical_slope_steps_per_m", c.vertical_slope_steps_per_m);
  c.vertical_offset_steps = readDouble(nh, "vertical_offset_steps", c.vertical_offset_steps);
  c.vertical_min_distance_m = readDouble(nh, "vertical_min_distance_m", c.vertical_min_distance_m);
  c.vertical_max_distance_m = readDouble(nh, "vertical_max_distance_m", c.vertical_max_distance_m);
  c.steps_per_rev = readDouble(nh, "steps_per_rev", c.steps_per_rev);
  c.belt_pitch_m = readDouble(nh, "belt_pitch_m", c.belt_pitch_m);
  c.pulley_teeth = readDouble(nh, "pulley_teeth", c.pulley_teeth);
  c.horizontal_min_m = readDouble(nh, "horizontal_min_m", c.horizontal_min_m);
  c.horizontal_max_m = readDouble(nh, "horizontal_max_m", c.horizontal_max_m);
  requireSound(nh, c.check());
  return c;
}

/// Rover controller parameters under `nh`.
inline RoverControllerParams loadRoverParams(const NodeParams& nh) {
  RoverControllerParams p;
  const std::string control = readString(nh, "position_control", toString(p.position_control));
  const auto parsed = parsePositionControl(control);
  if (!parsed) requireSound(nh, "position_control: expected 'deadband' or 'paper_pid' (got '" + control + "')");
  p.position_control = parsed.value_or(p.position_control);
  DeadbandControllerParams& d = p.deadband;
  d.forward_edge_pwm = readDouble(nh, "deadband/forward_edge_pwm", d.forward_edge_pwm);
  d.reverse_edge_pwm = readDouble(nh, "deadband/reverse_edge_pwm", d.reverse_edge_pwm);
  d.pwm_min = readDouble(nh, "deadband/pwm_min", d.pwm_min);
  d.pwm_max = readDouble(nh, "deadband/pwm_max", d.pwm_max);
  d.forward_mps_per_pwm = readDouble(nh, "deadband/forward_mps_per_pwm", d.forward_mps_per_pwm);
  d.reverse_mps_per_pwm = readDouble(nh, "deadband/reverse_mps_per_pwm", d.reverse_mps_per_pwm);
  d.max_speed_mps = readDouble(nh, "deadband/max_speed_mps", d.max_speed_mps);
  d.max_accel_mps2 = readDouble(nh, "deadband/max_accel_mps2", d.max_accel_mps2);
  d.position_gain = readDouble(nh, "deadband/position_gain", d.position_gain);
  d.integral_gain = readDouble(nh, "deadband/integral_gain", d.integral_gain);
  d.integral_limit_mps = readDouble(nh, "deadband/integral_limit_mps", d.integral_limit_mps);
  d.actuator_rate_pwm_per_s = readDouble(nh, "deadband/actuator_rate_pwm_per_s", d.actuator_rate_pwm_per_s);
  d.flow_lag_s = readDouble(nh, "deadband/flow_lag_s", d.flow_lag_s);
  d.edge_learning_pwm_per_s = readDouble(nh, "deadband/edge_learning_pwm_per_s", d.edge_learning_pwm_per_s);
  d.max_edge_correction_pwm = readDouble(nh, "deadband/max_edge_correction_pwm", d.max_edge_correction_pwm);
  d.stop_tolerance_m = readDouble(nh, "deadband/stop_tolerance_m", d.stop_tolerance_m);
  d.restart_tolerance_m = readDouble(nh, "deadband/restart_tolerance_m", d.restart_tolerance_m);
  p.pid.kp = readDouble(nh, "kp", p.pid.kp);
  p.pid.ki = readDouble(nh, "ki", p.pid.ki);
  p.pid.kd = readDouble(nh, "kd", p.pid.kd);
  p.pid.derivative_filter_s = readDouble(nh, "derivative_filter_s", p.pid.derivative_filter_s);
  p.swashplate.neutral_pwm = readDouble(nh, "neutral_pwm", p.swashplate.neutral_pwm);
  p.swashplate.forward_min_pwm = readDouble(nh, "forward_min_pwm", p.swashplate.forward_min_pwm);
  p.swashplate.forward_max_pwm = readDouble(nh, "forward_max_pwm", p.swashplate.forward_max_pwm);
  p.swashplate.reverse_min_pwm = readDouble(nh, "reverse_min_pwm", p.swashplate.reverse_min_pwm);
  p.swashplate.reverse_max_pwm = readDouble(nh, "reverse_max_pwm", p.swashplate.reverse_max_pwm);
  p.articulation.pot_center_counts = readDouble(nh, "pot_center_counts", p.articulation.pot_center_counts);
  p.articulation.pot_counts_per_deg = readDouble(nh, "pot_counts_per_deg", p.articulation.pot_counts_per_deg);
  p.articulation.limit_deg = readDouble(nh, "articulation_limit_deg", p.articulation.limit_deg);
  p.articulation.kp = readDouble(nh, "articulation_kp", p.articulation.kp);
  p.articulation.deadband_deg = readDouble(nh, "articulation_deadband_deg", p.articulation.deadband_deg);
  p.articulation.full_duty_deg = readDouble(nh, "articulation_full_duty_deg", p.articulation.full_duty_deg);
  p.articulation.relay_period_s = readDouble(nh, "relay_period_s", p.articulation.relay_period_s);
  p.metres_per_pulse = readDouble(nh, "metres_per_pulse", p.metres_per_pulse);
  p.position_tolerance_m = readDouble(nh, "position_tolerance_m", p.position_tolerance_m);
  p.velocity_lead_limit_m = readDouble(nh, "velocity_lead_limit_m", p.velocity_lead_limit_m);
  p.max_speed_mps = readDouble(nh, "max_speed_mps", p.max_speed_mps);
  p.feedforward_effort_per_mps = readDouble(nh, "feedforward_effort_per_mps", p.feedforward_effort_per_mps);
  p.axle_to_joint_m = readDouble(nh, "axle_to_joint_m", p.axle_to_joint_m);
  requireSound(nh, p.check());
  return p;
}

}  // namespace control
}  // namespace cotton_harvester
