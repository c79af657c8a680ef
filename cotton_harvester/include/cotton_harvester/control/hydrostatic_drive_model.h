#pragma once

#include <cstdint>

namespace cotton_harvester {
namespace control {

/// Physical figures of the simulated rover (paper §2.1, §2.3, §2.11; the speeds and lags are not
/// in the paper: assumptions, parameters).
struct HydrostaticDriveParams {
  double pwm_min = 65.0;           ///< servo range (§2.11): 65 full reverse
  double pwm_max = 120.0;          ///< 120 full forward
  double neutral_pwm = 90.0;       ///< swashplate neutral (§2.11)
  double deadband_low_pwm = 80.0;  ///< no flow between these two (§2.11: 80–98)
  double deadband_high_pwm = 98.0;
  double max_forward_speed_mps = 0.5;        ///< at pwm_max (assumption)
  double max_reverse_speed_mps = 0.5;        ///< at pwm_min (assumption)
  double actuator_rate_pwm_per_s = 12.0;     ///< linear actuator slew, in servo units (assumption)
  double flow_time_constant_s = 0.4;         ///< hydraulic first-order lag (assumption)
  double metres_per_pulse = 0.0018;          ///< encoder (§2.11)
  double articulation_rate_deg_per_s = 8.0;  ///< hydraulic cylinders with a relay on (assumption)
  double articulation_limit_deg = 45.0;      ///< §2.3
  double axle_to_joint_m = 0.91;             ///< front and rear axle to the articulation joint (§2.1)

  const char* check() const;  ///< empty when sound
};

/// The hydrostatic, centre-articulated rover as its navigation controller sees it: a servo PWM on
/// the swashplate actuator (slew-limited), a pump with a deadband, a lagging wheel speed, a wheel
/// encoder, and an articulation joint moved by two relays and read by a potentiometer.
class HydrostaticDriveModel {
 public:
  explicit HydrostaticDriveModel(const HydrostaticDriveParams& params = HydrostaticDriveParams());

  /// Advances the model by dt [s] with the servo PWM command and the relay states.
  void step(double pwm_command, bool relay_left, bool relay_right, double dt_s);

  /// Steady-state wheel speed [m/s] the pump gives at an actuator PWM (0 in the deadband).
  double flowSpeed(double pwm) const;

  double positionM() const { return position_m_; }
  double speedMps() const { return speed_mps_; }
  double actuatorPwm() const { return actuator_pwm_; }
  double articulationDeg() const { return articulation_deg_; }
  /// Encoder count: whole pulses travelled (signed).
  std::int32_t encoderCount() const;
  const HydrostaticDriveParams& params() const { return params_; }

  void setArticulationDeg(double angle_deg) { articulation_deg_ = angle_deg; }

 private:
  HydrostaticDriveParams params_;
  double position_m_ = 0.0;
  double speed_mps_ = 0.0;
  double actuator_pwm_ = 90.0;
  double articulation_deg_ = 0.0;
};

}  // namespace control
}  // namespace cotton_harvester
