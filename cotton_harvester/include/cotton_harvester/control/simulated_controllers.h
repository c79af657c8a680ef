#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "cotton_harvester/control/hydrostatic_drive_model.h"
#include "cotton_harvester/control/manipulator_protocol.h"
#include "cotton_harvester/control/navigation_protocol.h"
#include "cotton_harvester/control/stepper_axis_model.h"

namespace cotton_harvester {
namespace control {

/// Figures of the simulated manipulation controller and its two stepper axes.
struct SimulatedManipulatorParams {
  std::int32_t horizontal_min_steps = 0;
  std::int32_t horizontal_max_steps = 4200;  ///< 0.63 m of travel at 0.15 mm per step
  std::int32_t vertical_min_steps = 0;       ///< lowest point (eq. 7: 1.177 m from the camera)
  std::int32_t vertical_max_steps = 400;     ///< highest (eq. 7: 0.20 m from the camera)
  double horizontal_steps_per_s = 2000.0;    ///< assumption
  double vertical_steps_per_s = 150.0;       ///< assumption (about 0.37 m/s with eq. 7)
  std::int32_t horizontal_start_steps = 0;
  std::int32_t vertical_start_steps = 0;
  double report_period_s = 0.1;  ///< reports while an axis moves
};

/// The manipulation controller as the host sees it through the serial port: takes 4-byte commands,
/// runs the steppers, and answers with 4-byte reports (manipulator_protocol.h).
class SimulatedManipulationController {
 public:
  explicit SimulatedManipulationController(const SimulatedManipulatorParams& params = SimulatedManipulatorParams());

  /// Bytes from the host; returns the bytes to send back (answers to queries).
  std::vector<std::uint8_t> receive(const std::uint8_t* data, std::size_t size);
  /// Advances the steppers by dt [s]; returns reports to send (moves that ended, periodic).
  std::vector<std::uint8_t> step(double dt_s);

  const StepperAxisModel& horizontal() const { return horizontal_; }
  const StepperAxisModel& vertical() const { return vertical_; }
  bool brushOn() const { return brush_on_; }
  std::size_t rejectedBytes() const { return parser_.rejectedBytes(); }
  std::size_t commandsReceived() const { return commands_; }

 private:
  void appendReport(std::vector<std::uint8_t>* out, Axis axis) const;
  SimulatedManipulatorParams params_;
  StepperAxisModel horizontal_, vertical_;
  ManipulatorFrameParser parser_{0xA0};
  bool brush_on_ = false;
  double since_report_s_ = 0.0;
  std::size_t commands_ = 0;
};

/// Figures of the simulated navigation controller.
struct SimulatedNavigationParams {
  HydrostaticDriveParams drive;
  double pot_center_counts = 512.0;
  double pot_counts_per_deg = 5.0;
  double pot_noise_counts = 1.0;  ///< uniform ± noise on the ADC
  double telemetry_period_s = 0.02;
  double watchdog_s = 0.5;  ///< no drive command for this long: neutral, relays off
  unsigned seed = 7;
};

/// The navigation controller (an Arduino Mega on the rover) as the host sees it: takes drive
/// commands (servo PWM, relays), moves the hydrostatic drive model, and streams telemetry
/// (encoder count, potentiometer) every telemetry period (navigation_protocol.h).
class SimulatedNavigationController {
 public:
  explicit SimulatedNavigationController(const SimulatedNavigationParams& params = SimulatedNavigationParams());

  void receive(const std::uint8_t* data, std::size_t size);
  /// Advances by dt [s]; returns the telemetry frames due.
  std::vector<std::uint8_t> step(double dt_s);

  const HydrostaticDriveModel& drive() const { return drive_; }
  HydrostaticDriveModel& drive() { return drive_; }
  double commandedPwm() const { return pwm_; }
  bool watchdogStopped() const { return watchdog_stop_; }
  std::size_t commandsReceived() const { return commands_; }
  std::size_t rejectedBytes() const { return parser_.rejectedBytes(); }

 private:
  SimulatedNavigationParams params_;
  HydrostaticDriveModel drive_;
  NavigationFrameParser parser_;
  std::mt19937 rng_;
  double pwm_ = 90.0;
  bool left_ = false, right_ = false, clamped_ = false;
  bool watchdog_stop_ = true;
  double since_command_s_ = 1e9;
  double since_telemetry_s_ = 0.0;
  std::size_t commands_ = 0;
};

}  // namespace control
}  // namespace cotton_harvester
