#pragma once

#include <cstdint>

#include "cotton_harvester/control/manipulator_calibration.h"

namespace cotton_harvester {
namespace control {

/// One simulated stepper axis of the manipulator: moves a commanded number of steps at a constant
/// step rate and stops at its end stops.
class StepperAxisModel {
 public:
  StepperAxisModel(std::int32_t min_steps, std::int32_t max_steps, double steps_per_s, std::int32_t start_steps);

  /// Starts a relative move (replaces a move in progress).
  void start(bool positive, std::uint16_t steps);
  void stop();
  /// Advances by dt [s]; returns true when a move ended during this step.
  bool step(double dt_s);

  std::int32_t positionSteps() const { return position_; }
  bool moving() const { return remaining_ > 0; }
  /// The last move stopped at an end stop before its step count.
  bool limitHit() const { return limit_hit_; }

 private:
  std::int32_t min_, max_;
  double steps_per_s_;
  std::int32_t position_;
  std::int32_t remaining_ = 0;
  int direction_ = 1;
  double fraction_ = 0.0;
  bool limit_hit_ = false;
};

}  // namespace control
}  // namespace cotton_harvester
