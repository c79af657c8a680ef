#pragma once

#include <string>

namespace thorvald_base {

/// What base_driver asks one drive to do.
struct DriveCommand {
  double wheel_speed_radps = 0.0;  ///< wheel angular speed [rad/s], positive rolls base_link forward at angle 0
  double steering_rad = 0.0;       ///< steering angle about z [rad]; ignored by propulsion-only drives
};

/// What one drive reports.
struct DriveFeedback {
  double wheel_position_rad = 0.0;  ///< accumulated wheel angle [rad]
  double wheel_speed_radps = 0.0;   ///< wheel angular speed [rad/s]
  double steering_rad = 0.0;        ///< steering angle [rad]
  double steering_speed_radps = 0.0;
  bool valid = false;  ///< false until the first reading arrives
};

/// Health of one drive as its device reports it.
struct DriveStatus {
  bool online = true;   ///< feedback and heartbeat arrive
  bool fault = false;   ///< the controller reports a fault
  bool homing = false;  ///< steering homing in progress
  std::string text = "ok";
};

/// "lost" for a drive that is not online, followed by its device's reason when it gives one
/// ("lost (no feedback for 75 ms)"); the device's text otherwise.
inline std::string describe(const DriveStatus& s) {
  if (s.online) return s.text;
  return s.text.empty() || s.text == "ok" ? "lost" : "lost (" + s.text + ")";
}

}  // namespace thorvald_base
