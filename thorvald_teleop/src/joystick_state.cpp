#include "thorvald_teleop/joystick_state.h"

#include <algorithm>
#include <cmath>

namespace thorvald_teleop {

double scaleAxis(std::int16_t raw, double deadzone) {
  const double normalised = std::clamp(static_cast<double>(raw) / 32767.0, -1.0, 1.0);
  const double magnitude = std::abs(normalised);
  if (magnitude <= deadzone) return 0.0;
  const double stretched = (magnitude - deadzone) / (1.0 - deadzone);
  return normalised > 0.0 ? -stretched : stretched;
}

JoystickState::JoystickState(double deadzone, std::size_t axes, std::size_t buttons)
    : deadzone_(deadzone), axes_(axes, 0.0f), buttons_(buttons, 0) {}

void JoystickState::reset(std::size_t axes, std::size_t buttons) {
  axes_.assign(axes, 0.0f);
  buttons_.assign(buttons, 0);
}

bool JoystickState::apply(const JsEvent& event) {
  const std::uint8_t type = event.type & static_cast<std::uint8_t>(~kJsInit);
  const std::size_t index = event.number;
  if (type == kJsAxis) {
    const bool grown = index >= axes_.size();  // a new axis changes the published message too
    if (grown) axes_.resize(index + 1, 0.0f);
    const auto value = static_cast<float>(scaleAxis(event.value, deadzone_));
    const bool changed = grown || axes_[index] != value;
    axes_[index] = value;
    return changed;
  }
  if (type == kJsButton) {
    const bool grown = index >= buttons_.size();
    if (grown) buttons_.resize(index + 1, 0);
    const int value = event.value != 0 ? 1 : 0;
    const bool changed = grown || buttons_[index] != value;
    buttons_[index] = value;
    return changed;
  }
  ++unknown_events_;
  return false;
}

}  // namespace thorvald_teleop
