#pragma once

#include <vector>

namespace thorvald_teleop {

/// The axes and buttons of one sensor_msgs/Joy message.
struct JoyState {
  std::vector<float> axes;   ///< usually in [-1, 1]
  std::vector<int> buttons;  ///< 1 pressed, 0 released
};

/// Value of axis `index`; 0 when the index is negative or beyond the message (teleop_twist_joy's rule).
inline double axisValue(const JoyState& joy, int index) {
  return index >= 0 && static_cast<std::size_t>(index) < joy.axes.size() ? joy.axes[static_cast<std::size_t>(index)]
                                                                         : 0.0;
}

/// True when button `index` exists in the message and is pressed.
inline bool buttonPressed(const JoyState& joy, int index) {
  return index >= 0 && static_cast<std::size_t>(index) < joy.buttons.size() &&
         joy.buttons[static_cast<std::size_t>(index)] != 0;
}

}  // namespace thorvald_teleop
