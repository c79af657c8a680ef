#pragma once

#include <string>

namespace cotton_harvester {
namespace control {

/// Parameters of the deadband-aware position controller of the hydrostatic drive. The speed map is the
/// pump's: no flow between the deadband edges, then a speed proportional to the PWM past the edge.
struct DeadbandControllerParams {
  double neutral_pwm = 90.0;                ///< swashplate neutral (paper §2.11) [servo units]
  double forward_edge_pwm = 98.0;           ///< flow starts forward past this (paper §2.11: deadband 80-98)
  double reverse_edge_pwm = 80.0;           ///< flow starts in reverse below this
  double pwm_min = 65.0;                    ///< full reverse (paper §2.11)
  double pwm_max = 120.0;                   ///< full forward (paper §2.11)
  double forward_mps_per_pwm = 0.5 / 22.0;  ///< forward speed per servo unit past the edge [m/s]; measure it
  double reverse_mps_per_pwm = 0.5 / 15.0;  ///< reverse speed per servo unit past the edge [m/s]; measure it
  double max_speed_mps = 0.35;              ///< cruise speed of the velocity profile [m/s]
  double max_accel_mps2 = 0.15;             ///< acceleration and deceleration of the profile [m/s^2]; keep the PWM
                                            ///< rate it asks (accel / speed per PWM) below the actuator's slew rate
  double position_gain = 0.8;               ///< speed correction per metre of error against the profile [1/s]
  double integral_gain = 0.05;              ///< [1/s^2]; the integral is limited to +-integral_limit_mps
  double integral_limit_mps = 0.03;         ///< anti-windup bound of the integral term [m/s]
  double speed_filter_s = 0.1;              ///< low-pass time constant of the encoder speed [s]
  double actuator_rate_pwm_per_s = 12.0;    ///< slew rate of the swashplate's linear actuator [servo units/s]
  double flow_lag_s = 0.4;                  ///< first-order lag of the wheel speed behind the swashplate [s]
  /// The deadband's edges are learnt: while a command past an edge has reached the actuator and the rover does not
  /// move, that edge is moved outwards at this rate, up to max_edge_correction_pwm [servo units/s].
  double edge_learning_pwm_per_s = 2.0;
  double max_edge_correction_pwm = 6.0;  ///< [servo units]
  double stop_tolerance_m = 0.01;        ///< at rest within this of the target: hold the neutral [m]
  double restart_tolerance_m = 0.04;     ///< at rest farther than this from the target: move again [m]

  /// Empty when sound, otherwise "key: expected ...".
  std::string check() const;
};

/// A position controller that knows the hydrostatic drive: a trapezoidal velocity profile towards the target, the
/// profile's speed as feedforward through the inverse deadband map (so no effort is spent inside the band), a
/// proportional and a bounded integral correction on the error against the profile (anti-windup: the integral
/// stops growing while the speed command is saturated and is cleared at rest), and a stop that returns the
/// swashplate to neutral early by the distance the rover coasts. The actuator's slew is modelled from the commands
/// sent: the profile waits while the actuator crosses the deadband, commands are slew-limited, and the coast
/// distance counts the actuator's travel back to the edge and the hydraulic lag. Time steps come from the caller.
class DeadbandPositionController {
 public:
  explicit DeadbandPositionController(const DeadbandControllerParams& params = DeadbandControllerParams());

  /// A new target [m]; the profile starts from the current position and speed.
  void setTarget(double target_m);
  /// Velocity mode: the target moves at this speed [m/s] (|speed| <= max_speed_mps).
  void setVelocity(double speed_mps);
  /// Leaves velocity mode and stops along the profile: the target becomes where the profile comes to rest at its
  /// deceleration (rather than where the rover is now, which it has already passed when it can stop).
  void stop();
  /// Forgets the profile and the integral; the next update starts from the measured position.
  void reset();

  /// One step: measured position [m], dt [s] > 0. Returns the servo PWM.
  double update(double position_m, double dt_s);

  double referenceM() const { return reference_m_; }
  double referenceSpeedMps() const { return reference_mps_; }
  double speedMps() const { return speed_mps_; }
  double targetM() const { return target_m_; }
  double forwardEdgeCorrectionPwm() const { return forward_correction_pwm_; }
  double reverseEdgeCorrectionPwm() const { return reverse_correction_pwm_; }
  bool atRest() const { return at_rest_; }
  /// Servo PWM for a wanted speed [m/s]: the inverse of the deadband map (neutral for 0).
  double pwmForSpeed(double speed_mps) const;

 private:
  void advanceProfile(double dt_s);
  double send(double pwm, double dt_s);  ///< advances the actuator model towards pwm, returns pwm

  DeadbandControllerParams params_;
  bool initialised_ = false;
  bool velocity_mode_ = false;
  bool at_rest_ = true;
  double target_m_ = 0.0;
  double velocity_mps_ = 0.0;
  double reference_m_ = 0.0;
  double reference_mps_ = 0.0;
  double last_position_m_ = 0.0;
  double speed_mps_ = 0.0;
  double integral_mps_ = 0.0;
  double actuator_pwm_ = 0.0;            ///< the actuator's position as the sent commands and its slew predict
  double forward_correction_pwm_ = 0.0;  ///< learnt outward shift of the forward edge
  double reverse_correction_pwm_ = 0.0;  ///< learnt outward shift of the reverse edge
};

}  // namespace control
}  // namespace cotton_harvester
