#include "cotton_harvester/control/position_pid.h"

#include <algorithm>
#include <cmath>

namespace cotton_harvester {
namespace control {

double PositionPid::update(double setpoint, double measurement, double dt_s, double setpoint_rate, double feedforward) {
  if (!std::isfinite(setpoint) || !std::isfinite(measurement) || !std::isfinite(dt_s) || dt_s <= 0.0 ||
      !std::isfinite(setpoint_rate) || !std::isfinite(feedforward)) {
    return last_output_;
  }
  const double error = setpoint - measurement;
  if (has_last_) {
    const double rate = (measurement - last_measurement_) / dt_s;
    const double alpha = gains_.derivative_filter_s > 0.0 ? 1.0 - std::exp(-dt_s / gains_.derivative_filter_s) : 1.0;
    filtered_rate_ += alpha * (rate - filtered_rate_);
  }
  const double derivative = setpoint_rate - filtered_rate_;
  last_measurement_ = measurement;
  has_last_ = true;

  const double proportional = gains_.kp * error;
  const double damping = gains_.kd * derivative;
  const double candidate_integral = integral_ + gains_.ki * error * dt_s;
  const double unsaturated = proportional + candidate_integral + damping + feedforward;
  // Conditional integration: keep the new integral unless it pushes a saturated output further out.
  const bool pushes_high = unsaturated > gains_.output_max && error > 0.0;
  const bool pushes_low = unsaturated < gains_.output_min && error < 0.0;
  if (!pushes_high && !pushes_low) integral_ = candidate_integral;
  integral_ = std::clamp(integral_, gains_.output_min, gains_.output_max);

  last_output_ = std::clamp(proportional + integral_ + damping + feedforward, gains_.output_min, gains_.output_max);
  return last_output_;
}

void PositionPid::reset() {
  integral_ = 0.0;
  has_last_ = false;
  filtered_rate_ = 0.0;
  last_output_ = 0.0;
}

}  // namespace control
}  // namespace cotton_harvester
