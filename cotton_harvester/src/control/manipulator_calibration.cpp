#include "cotton_harvester/control/manipulator_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cotton_harvester {
namespace control {

std::string ManipulatorCalibration::check() const {
  if (!(std::isfinite(vertical_slope_steps_per_m) && vertical_slope_steps_per_m != 0.0))
    return "vertical_slope_steps_per_m: expected a finite non-zero slope (paper: -410.7)";
  if (!std::isfinite(vertical_offset_steps)) return "vertical_offset_steps: expected a finite value (paper: 483.29)";
  if (!(vertical_min_distance_m > 0.0 && vertical_min_distance_m < vertical_max_distance_m))
    return "vertical_min_distance_m: expected 0 < min < vertical_max_distance_m";
  if (!(steps_per_rev > 0.0)) return "steps_per_rev: expected > 0 (paper: 400)";
  if (!(belt_pitch_m > 0.0)) return "belt_pitch_m: expected > 0 (paper: 0.003)";
  if (!(pulley_teeth >= 1.0)) return "pulley_teeth: expected >= 1";
  if (!(horizontal_min_m >= 0.0 && horizontal_min_m < horizontal_max_m))
    return "horizontal_min_m: expected 0 <= min < horizontal_max_m";
  const double span_v =
      std::abs(verticalStepsFromDistance(vertical_max_distance_m) - verticalStepsFromDistance(vertical_min_distance_m));
  const double span_h = horizontalStepsFromExtension(horizontal_max_m);
  if (span_v > 32767.0 || span_h > 32767.0)
    return "axis span: expected at most 32767 steps per axis (the reply carries an int16 position)";
  return "";
}

double ManipulatorCalibration::verticalStepsFromDistance(double distance_m) const {
  return vertical_slope_steps_per_m * distance_m + vertical_offset_steps;
}

double ManipulatorCalibration::verticalDistanceFromSteps(double steps) const {
  return (steps - vertical_offset_steps) / vertical_slope_steps_per_m;
}

double ManipulatorCalibration::horizontalStepsFromExtension(double extension_m) const {
  return extension_m / horizontalMetresPerStep();
}

double ManipulatorCalibration::horizontalExtensionFromSteps(double steps) const {
  return steps * horizontalMetresPerStep();
}

std::int32_t ManipulatorCalibration::targetSteps(Axis axis, double position_m, bool* clamped) const {
  double lo = axis == Axis::kVertical ? vertical_min_distance_m : horizontal_min_m;
  double hi = axis == Axis::kVertical ? vertical_max_distance_m : horizontal_max_m;
  const double limited = std::isfinite(position_m) ? std::clamp(position_m, lo, hi) : lo;
  if (clamped) *clamped = !(limited == position_m);
  const double steps =
      axis == Axis::kVertical ? verticalStepsFromDistance(limited) : horizontalStepsFromExtension(limited);
  return static_cast<std::int32_t>(std::lround(steps));
}

StepMove ManipulatorCalibration::moveBetween(Axis axis, std::int32_t current_steps, std::int32_t target_steps,
                                             std::int32_t* remaining) {
  const std::int64_t delta = static_cast<std::int64_t>(target_steps) - current_steps;
  const std::int64_t magnitude = std::min<std::int64_t>(std::llabs(delta), std::numeric_limits<std::uint16_t>::max());
  StepMove move;
  move.axis = axis;
  move.positive = delta >= 0;
  move.steps = static_cast<std::uint16_t>(magnitude);
  if (remaining) *remaining = static_cast<std::int32_t>(delta - (delta >= 0 ? magnitude : -magnitude));
  return move;
}

}  // namespace control
}  // namespace cotton_harvester
