#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "cotton_harvester/control/manipulator_calibration.h"
#include "cotton_harvester/control/navigation_protocol.h"
#include "cotton_harvester/control/simulated_controllers.h"
#include "cotton_harvester_sim/rover_sim.h"

namespace cotton_harvester {
namespace sim {

/// Figures of the two serial controllers in front of the simulated rover.
struct SerialBridgeParams {
  /// The manipulation controller's steppers: counts <-> metres of the simulated arm (eq. 7 vertical, the belt
  /// horizontal). The stack's manipulator node must be given the same calibration (what a user measures).
  control::ManipulatorCalibration calibration;
  double vertical_steps_per_s = 150.0;     ///< the steppers' rates (0.365 m/s and 0.30 m/s: RoverSimParams)
  double horizontal_steps_per_s = 2000.0;  ///<
  double report_period_s = 0.1;            ///< manipulation reports while an axis moves
  double pot_center_counts = 512.0;        ///< articulation potentiometer
  double pot_counts_per_deg = 5.0;
  double pot_noise_counts = 1.0;         ///< uniform +- noise on the ADC
  double telemetry_period_s = 0.02;      ///< navigation telemetry (50 Hz)
  double watchdog_s = 0.5;               ///< no drive command for this long: neutral, relays off
  double articulation_rate_deg_s = 8.0;  ///< the valve turns the joint this fast while a relay is on
  unsigned seed = 7;
  std::string check() const;  ///< empty when sound
};

/// The rover's two serial controllers (manipulation and navigation) in front of a RoverSim: the same byte
/// protocols as the hardware (manipulator_protocol.h, navigation_protocol.h) and simulated_controller, but the
/// drive, the articulation, the arm and the vacuum they command are MuJoCo's, and the encoder and potentiometer they
/// report are read from it. The manipulation controller counts steps (open loop, as the real one); the simulated
/// arm follows the counters at the steppers' rates. ROS-free; not thread-safe.
class RoverSerialBridge {
 public:
  /// Throws std::invalid_argument on bad parameters. Sets the step counters to where the simulated arm is.
  RoverSerialBridge(RoverSim& sim, const SerialBridgeParams& params);

  /// Bytes from the host on the manipulation link; returns the bytes to send back (answers to queries).
  std::vector<std::uint8_t> receiveManipulator(const std::uint8_t* data, std::size_t size);
  /// Bytes from the host on the navigation link.
  void receiveNavigation(const std::uint8_t* data, std::size_t size);

  /// Frames due on either link after advance().
  struct Output {
    std::vector<std::uint8_t> manipulator, navigation;
  };
  /// Applies the commands to the simulated rover, advances its physics by dt [s] and returns the frames due.
  Output advance(double dt_s);

  double commandedPwm() const { return pwm_; }
  bool watchdogStopped() const { return watchdog_stop_; }
  std::size_t driveCommands() const { return drive_commands_; }
  std::size_t rejectedBytes() const { return parser_.rejectedBytes() + manipulator_.rejectedBytes(); }
  const control::SimulatedManipulationController& manipulator() const { return manipulator_; }

 private:
  RoverSim& sim_;
  SerialBridgeParams params_;
  control::SimulatedManipulationController manipulator_;
  control::NavigationFrameParser parser_;
  std::mt19937 rng_;
  double pwm_ = 90.0;
  double articulation_deg_ = 0.0;
  bool left_ = false, right_ = false, clamped_ = false, watchdog_stop_ = true;
  double since_command_s_ = 1e9, since_telemetry_s_ = 0.0;
  std::size_t drive_commands_ = 0;
};

/// The calibration of the simulated rover's arm: eq. 7 over the vertical axis' whole travel (0.30-1.93 m below the
/// camera) and the belt over its 0.70 m horizontal travel.
control::ManipulatorCalibration simArmCalibration(const RoverGeometry& geometry);

}  // namespace sim
}  // namespace cotton_harvester
