#pragma once

#include <optional>
#include <string>

#include "thorvald_teleop/drive_mode.h"
#include "thorvald_teleop/joy_state.h"
#include "thorvald_teleop/twist_joy_mapping.h"
#include "thorvald_teleop/velocity_command.h"

namespace thorvald_teleop {

/// Buttons of the Thorvald additions; -1 leaves a function unassigned (the default: plain teleop_twist_joy).
struct TeleopButtons {
  int mode_omni = -1;
  int mode_drive = -1;
  int mode_turn = -1;
  int gain_up = -1;
  int gain_down = -1;
  int priority = -1;       ///< toggles the priority lock that lets the pad override autonomy
  int home_steering = -1;  ///< requests steering homing; only while the enable button is held
};

/// The speed gain multiplying every component, stepped by buttons within [min, max].
struct GainRange {
  double initial = 1.0;
  double min = 0.1;
  double max = 1.0;
  double step = 0.1;
};

struct JoyTeleopConfig {
  TwistJoyMapping mapping = TwistJoyMapping::defaults();
  TeleopButtons buttons;
  GainRange gain;
  DriveMode initial_mode = DriveMode::kOmni;
  double joy_timeout_s = 0.0;  ///< [s] deadman: zero twist when no Joy for this long while driving; 0 = off
};

/// Returns an empty string or a message naming the bad key and the expected value.
std::string validateTeleopConfig(const JoyTeleopConfig& config);

/// What the node should do after an event.
struct TeleopActions {
  std::optional<VelocityCommand> command;  ///< publish on cmd_vel
  std::optional<bool> priority;            ///< publish the priority lock
  bool home_steering = false;              ///< call the steering homing service
  bool mode_changed = false;
  bool gain_changed = false;
  bool non_finite_axes = false;  ///< the message had NaN or infinite axes; they were read as 0 (centred)
};

/// teleop_twist_joy's behaviour plus the Thorvald additions. Turbo drives without enable; with enable released one
/// zero command is sent; nothing is sent before the first Joy. Buttons act on their press (rising edge). An axis
/// that is NaN or infinite (a broken driver or device) is read as centred (0): its component of the command stops,
/// it never reaches cmd_vel; such messages are counted. Times are seconds on the caller's clock.
class JoyTeleop {
 public:
  explicit JoyTeleop(JoyTeleopConfig config);

  TeleopActions onJoy(const JoyState& message, double now_s);
  /// Deadman check, called periodically: one zero command when Joy messages stopped while driving.
  TeleopActions onTimer(double now_s);

  const JoyTeleopConfig& config() const { return config_; }
  DriveMode mode() const { return mode_; }
  double gain() const { return gain_; }
  bool priority() const { return priority_; }
  unsigned long deadmanStops() const { return deadman_stops_; }
  /// Joy messages that had at least one NaN or infinite axis.
  unsigned long nonFiniteMessages() const { return non_finite_messages_; }
  /// Age of the last Joy message [s]; negative before the first.
  double joyAge(double now_s) const { return heard_ ? now_s - last_joy_s_ : -1.0; }

 private:
  bool pressedNow(const JoyState& joy, int button) const;
  void handleButtons(const JoyState& joy, TeleopActions& actions);

  JoyTeleopConfig config_;
  DriveMode mode_;
  double gain_;
  bool priority_ = false;
  bool heard_ = false;
  double last_joy_s_ = 0.0;
  bool stopped_ = false;  ///< the last command sent was the stop after release (or the deadman's)
  JoyState previous_;
  unsigned long deadman_stops_ = 0;
  unsigned long non_finite_messages_ = 0;
};

}  // namespace thorvald_teleop
