#pragma once

namespace cotton_harvester {
namespace control {

/// Gains and limits of the rover's position PID (paper §2.11: the second tuning Kp 0.7, Ki 0.04,
/// Kd 5.0 on an error in encoder pulses, output u in [-100, 100]).
struct PidGains {
  double kp = 0.7;   ///< [1/pulse]
  double ki = 0.04;  ///< [1/(pulse s)]
  double kd = 5.0;   ///< [s/pulse]
  double output_min = -100.0;
  double output_max = 100.0;
  double derivative_filter_s = 0.1;  ///< time constant of the low-pass on the derivative [s] (0: none);
                                     ///< one 1.8 mm pulse in a 20 ms period is otherwise a 250-unit kick
};

/// PID on position with a low-passed derivative on the measurement (no kick on a new target) and
/// anti-windup by
/// conditional integration: the integral only grows while the output is not saturated in the
/// direction of the error, and it is clamped to the output range.
class PositionPid {
 public:
  explicit PositionPid(const PidGains& gains = PidGains()) : gains_(gains) {}

  /// One control step. `setpoint` and `measurement` in the same unit (pulses), `dt_s` > 0 [s].
  /// `setpoint_rate` [unit/s]: how fast the setpoint moves (a ramp); the derivative then damps the
  /// rate error instead of the rate. `feedforward` is added to the output (output units).
  /// Returns u in [output_min, output_max]; a non-finite input or dt <= 0 returns the last output.
  double update(double setpoint, double measurement, double dt_s, double setpoint_rate = 0.0, double feedforward = 0.0);

  /// Forgets the integral and the derivative history (next update has no derivative term).
  void reset();

  void setGains(const PidGains& gains) { gains_ = gains; }
  const PidGains& gains() const { return gains_; }
  double integral() const { return integral_; }
  double lastOutput() const { return last_output_; }

 private:
  PidGains gains_;
  double integral_ = 0.0;  ///< already multiplied by ki [output units]
  double last_measurement_ = 0.0;
  double filtered_rate_ = 0.0;  ///< low-passed d(measurement)/dt
  bool has_last_ = false;
  double last_output_ = 0.0;
};

}  // namespace control
}  // namespace cotton_harvester
