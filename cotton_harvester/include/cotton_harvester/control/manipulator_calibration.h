#pragma once

#include <cstdint>
#include <string>

namespace cotton_harvester {
namespace control {

/// The two Cartesian axes of the manipulator (§2.4).
enum class Axis : std::uint8_t { kHorizontal = 0, kVertical = 1 };

/// A relative stepper move, as the 4-byte command carries it.
struct StepMove {
  Axis axis = Axis::kHorizontal;
  bool positive = true;     ///< direction: the axis' step counter increases
  std::uint16_t steps = 0;  ///< number of steps
};

/// Calibration and limits of the manipulator.
///  - Vertical axis (camera looks down): the end effector's distance from the camera d [m] maps to
///    an absolute step position by the paper's fit, eq. 7: steps = -410.7 d + 483.29 (R² = 0.99).
///  - Horizontal axis: toothed belt (3 mm pitch) on a pulley of `pulley_teeth` teeth, driven at
///    400 steps per revolution: steps = extension / (pitch × teeth / 400).
struct ManipulatorCalibration {
  double vertical_slope_steps_per_m = -410.7;  ///< eq. 7 slope
  double vertical_offset_steps = 483.29;       ///< eq. 7 intercept
  double vertical_min_distance_m = 0.30;       ///< closest to the camera the end effector may go
  double vertical_max_distance_m = 1.17;       ///< farthest (eq. 7 reaches 0 steps at 1.177 m)
  double steps_per_rev = 400.0;                ///< micro-stepping drive setting (§2.4)
  double belt_pitch_m = 0.003;                 ///< toothed belt pitch (§2.4)
  double pulley_teeth = 20.0;                  ///< not in the paper: an assumption, a parameter
  double horizontal_min_m = 0.0;               ///< retracted
  double horizontal_max_m = 0.60;              ///< horizontal arm length (§2.4)

  /// Empty when sound, otherwise "key: what was expected".
  std::string check() const;

  /// Horizontal travel per step [m].
  double horizontalMetresPerStep() const { return belt_pitch_m * pulley_teeth / steps_per_rev; }

  /// eq. 7: absolute vertical step position for a distance from the camera [m] (not rounded).
  double verticalStepsFromDistance(double distance_m) const;
  /// Inverse of eq. 7: distance from the camera [m] of an absolute vertical step position.
  double verticalDistanceFromSteps(double steps) const;
  /// Absolute horizontal step position for an extension [m] (not rounded).
  double horizontalStepsFromExtension(double extension_m) const;
  double horizontalExtensionFromSteps(double steps) const;

  /// Absolute step position of a target on `axis` (position in that axis' metres: extension for
  /// the horizontal axis, distance from the camera for the vertical one), clamped to the axis
  /// limits and rounded. `clamped` is set when the target was outside the limits.
  std::int32_t targetSteps(Axis axis, double position_m, bool* clamped = nullptr) const;

  /// The relative move from `current_steps` to `target_steps` (at most 65535 steps per command;
  /// longer moves need several commands, `remaining` gets what is left).
  static StepMove moveBetween(Axis axis, std::int32_t current_steps, std::int32_t target_steps,
                              std::int32_t* remaining = nullptr);
};

}  // namespace control
}  // namespace cotton_harvester
