#include "cotton_harvester/control/stepper_axis_model.h"

#include <algorithm>
#include <cmath>

namespace cotton_harvester {
namespace control {

StepperAxisModel::StepperAxisModel(std::int32_t min_steps, std::int32_t max_steps, double steps_per_s,
                                   std::int32_t start_steps)
    : min_(min_steps),
      max_(max_steps),
      steps_per_s_(steps_per_s),
      position_(std::clamp(start_steps, min_steps, max_steps)) {}

void StepperAxisModel::start(bool positive, std::uint16_t steps) {
  direction_ = positive ? 1 : -1;
  remaining_ = steps;
  fraction_ = 0.0;
  limit_hit_ = false;
}

void StepperAxisModel::stop() {
  remaining_ = 0;
  fraction_ = 0.0;
}

bool StepperAxisModel::step(double dt_s) {
  if (remaining_ <= 0 || !(dt_s > 0.0)) return false;
  fraction_ += steps_per_s_ * dt_s;
  auto whole = static_cast<std::int32_t>(std::floor(fraction_));
  fraction_ -= whole;
  whole = std::min(whole, remaining_);
  const std::int32_t room = direction_ > 0 ? max_ - position_ : position_ - min_;
  if (whole >= room && remaining_ > room) {
    position_ += direction_ * room;
    remaining_ = 0;
    limit_hit_ = true;
    return true;
  }
  position_ += direction_ * whole;
  remaining_ -= whole;
  return remaining_ == 0;
}

}  // namespace control
}  // namespace cotton_harvester
