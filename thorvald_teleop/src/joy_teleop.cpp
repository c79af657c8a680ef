#include "thorvald_teleop/joy_teleop.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace thorvald_teleop {

std::string validateTeleopConfig(const JoyTeleopConfig& config) {
  const std::string mapping_error = validateMapping(config.mapping);
  if (!mapping_error.empty()) return mapping_error;
  const GainRange& g = config.gain;
  if (!(std::isfinite(g.min) && g.min > 0.0)) return "gain_min is " + std::to_string(g.min) + ", expected > 0";
  if (!(std::isfinite(g.max) && g.max >= g.min)) {
    return "gain_max is " + std::to_string(g.max) + ", expected >= gain_min (" + std::to_string(g.min) + ")";
  }
  if (!(g.initial >= g.min && g.initial <= g.max)) {
    return "gain is " + std::to_string(g.initial) + ", expected within [gain_min, gain_max]";
  }
  if (!(std::isfinite(g.step) && g.step > 0.0)) return "gain_step is " + std::to_string(g.step) + ", expected > 0";
  if (!(std::isfinite(config.joy_timeout_s) && config.joy_timeout_s >= 0.0)) {
    return "joy_timeout is " + std::to_string(config.joy_timeout_s) + ", expected >= 0 [s] (0 = off)";
  }
  return {};
}

JoyTeleop::JoyTeleop(JoyTeleopConfig config)
    : config_(std::move(config)), mode_(config_.initial_mode), gain_(config_.gain.initial) {}

bool JoyTeleop::pressedNow(const JoyState& joy, int button) const {
  return buttonPressed(joy, button) && !buttonPressed(previous_, button);
}

void JoyTeleop::handleButtons(const JoyState& joy, TeleopActions& actions) {
  const TeleopButtons& b = config_.buttons;
  const std::pair<int, DriveMode> modes[] = {
      {b.mode_omni, DriveMode::kOmni}, {b.mode_drive, DriveMode::kDrive}, {b.mode_turn, DriveMode::kTurnInPlace}};
  for (const auto& [button, mode] : modes) {
    if (pressedNow(joy, button) && mode_ != mode) {
      mode_ = mode;
      actions.mode_changed = true;
    }
  }
  const GainRange& g = config_.gain;
  // Stepping in whole steps from the minimum keeps the gain on a grid (no drift from repeated additions).
  auto snap = [&](double value) { return g.min + std::round((value - g.min) / g.step) * g.step; };
  if (pressedNow(joy, b.gain_up)) {
    const double next = std::min(g.max, snap(gain_ + g.step));
    actions.gain_changed = next != gain_;
    gain_ = next;
  }
  if (pressedNow(joy, b.gain_down)) {
    const double next = std::max(g.min, snap(gain_ - g.step));
    actions.gain_changed = actions.gain_changed || next != gain_;
    gain_ = next;
  }
  if (pressedNow(joy, b.priority)) {
    priority_ = !priority_;
    actions.priority = priority_;
  }
  const TwistJoyMapping& m = config_.mapping;
  const bool enabled = !m.require_enable_button || buttonPressed(joy, m.enable_button);
  if (pressedNow(joy, b.home_steering) && enabled) actions.home_steering = true;
}

TeleopActions JoyTeleop::onJoy(const JoyState& message, double now_s) {
  TeleopActions actions;
  JoyState joy = message;
  for (float& axis : joy.axes) {
    if (std::isfinite(axis)) continue;
    axis = 0.0f;
    actions.non_finite_axes = true;
  }
  if (actions.non_finite_axes) ++non_finite_messages_;
  heard_ = true;
  last_joy_s_ = now_s;
  handleButtons(joy, actions);
  const TwistJoyMapping& m = config_.mapping;
  const bool turbo = buttonPressed(joy, m.enable_turbo_button);
  const bool enabled = !m.require_enable_button || buttonPressed(joy, m.enable_button);
  if (turbo || enabled) {
    actions.command = applyDriveMode(commandFromJoy(joy, m, turbo), mode_).scaled(gain_);
    stopped_ = false;
  } else if (!stopped_) {
    actions.command = VelocityCommand();
    stopped_ = true;
  }
  previous_ = joy;
  return actions;
}

TeleopActions JoyTeleop::onTimer(double now_s) {
  TeleopActions actions;
  if (config_.joy_timeout_s <= 0.0 || !heard_ || stopped_) return actions;
  if (now_s - last_joy_s_ <= config_.joy_timeout_s) return actions;
  actions.command = VelocityCommand();
  stopped_ = true;
  ++deadman_stops_;
  return actions;
}

}  // namespace thorvald_teleop
