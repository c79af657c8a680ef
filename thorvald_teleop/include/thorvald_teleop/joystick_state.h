#pragma once

#include <cstdint>
#include <vector>

namespace thorvald_teleop {

/// One event of the Linux joystick API (linux/joystick.h `struct js_event`), 8 bytes as the kernel writes them.
struct JsEvent {
  std::uint32_t time_ms;  ///< [ms] kernel event time
  std::int16_t value;     ///< axis -32767..32767, button 0/1
  std::uint8_t type;      ///< kJsButton or kJsAxis, possibly or'ed with kJsInit
  std::uint8_t number;    ///< axis or button index
};
static_assert(sizeof(JsEvent) == 8, "JsEvent must match the kernel's struct js_event");

constexpr std::uint8_t kJsButton = 0x01;
constexpr std::uint8_t kJsAxis = 0x02;
constexpr std::uint8_t kJsInit = 0x80;

/// Maps a raw axis value to [-1, 1] with a dead zone, in the joy package's convention: the sign is inverted (stick
/// up/left reads positive) and the range outside the dead zone is stretched to reach 1 at full deflection.
/// `deadzone` in [0, 1) is the fraction of full scale around 0 that reads 0.
double scaleAxis(std::int16_t raw, double deadzone);

/// The pad's current axes and buttons, built from events. Arrays grow to the highest index seen (or are sized
/// from the device's counts); events with another type are ignored and counted.
class JoystickState {
 public:
  explicit JoystickState(double deadzone, std::size_t axes = 0, std::size_t buttons = 0);

  /// Applies one event; returns true when a published value changed.
  bool apply(const JsEvent& event);
  void reset(std::size_t axes, std::size_t buttons);

  const std::vector<float>& axes() const { return axes_; }
  const std::vector<int>& buttons() const { return buttons_; }
  unsigned long unknownEvents() const { return unknown_events_; }

 private:
  double deadzone_;
  std::vector<float> axes_;
  std::vector<int> buttons_;
  unsigned long unknown_events_ = 0;
};

}  // namespace thorvald_teleop
