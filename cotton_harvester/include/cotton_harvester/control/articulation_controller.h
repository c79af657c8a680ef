#pragma once

namespace cotton_harvester {
namespace control {

/// Relay outputs of the articulation valve (paper §2.12): left turns to positive angles.
struct RelayCommand {
  bool left = false;
  bool right = false;
};

/// Potentiometer calibration and limits of the articulation joint.
struct ArticulationParams {
  double pot_center_counts = 512.0;  ///< ADC reading when the rover is straight
  double pot_counts_per_deg = 5.0;   ///< ADC counts per degree, positive to the left
  double limit_deg = 45.0;           ///< the rover turns at most ±45° (§2.3)
  double kp = 1.0;                   ///< proportional gain [1] (§2.12)
  double deadband_deg = 1.0;         ///< |Kp e| below this: both relays off
  double full_duty_deg = 5.0;        ///< |Kp e| at or above this: relay on for the whole period
  double relay_period_s = 0.2;       ///< time-proportioning period of the relays

  const char* check() const;  ///< empty when sound
};

/// Proportional control of the articulation angle through two on/off relays. The P output Kp e
/// [deg] sets the relay's duty within each period (time-proportioning), so the hydraulic cylinders
/// slow down near the target instead of chattering.
class ArticulationController {
 public:
  explicit ArticulationController(const ArticulationParams& params = ArticulationParams()) : params_(params) {}

  /// Angle [deg] from a potentiometer reading [ADC counts].
  double angleFromPot(double counts) const;
  /// Potentiometer reading [counts] for an angle [deg] (the simulator uses it).
  double potFromAngle(double angle_deg) const;

  /// One step: target and measured angle [deg], dt [s]. The target is clamped to ±limit_deg.
  RelayCommand update(double target_deg, double measured_deg, double dt_s);

  const ArticulationParams& params() const { return params_; }

 private:
  ArticulationParams params_;
  double phase_s_ = 0.0;
};

}  // namespace control
}  // namespace cotton_harvester
