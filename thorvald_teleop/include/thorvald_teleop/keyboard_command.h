#pragma once

#include <optional>
#include <string>

#include "thorvald_teleop/key_decoder.h"
#include "thorvald_teleop/velocity_command.h"

namespace thorvald_teleop {

struct KeyboardConfig {
  double linear_speed_max = 1.0;   ///< [m/s] at gain 1
  double angular_speed_max = 1.0;  ///< [rad/s] at gain 1
  double gain = 0.5;               ///< initial fraction of the maximum speeds
  double gain_step = 0.1;          ///< change per '+' / '-'
  double gain_min = 0.1;
  double gain_max = 1.0;
  double key_timeout_s = 0.7;  ///< [s] stop when no motion key for this long; 0 = keep the last command
};

/// Returns an empty string or a message naming the bad key and the expected value.
std::string validateKeyboardConfig(const KeyboardConfig& config);

/// What a key did.
struct KeyboardActions {
  std::optional<VelocityCommand> command;  ///< publish
  bool quit = false;                       ///< Ctrl-C or Ctrl-D: stop and leave
  bool show_help = false;
  bool gain_changed = false;
};

/// Keyboard driving: w/Up forward, s/Down back, a/Left turn left, d/Right turn right, q/e crab left/right,
/// space or x stop, + and - step the speed, h or ? help, Ctrl-C/Ctrl-D quit (with a stop). A motion key sets the
/// command until another key, a stop, or key_timeout without motion keys (terminal auto-repeat keeps a held key
/// alive). Times in seconds on the caller's clock.
class KeyboardCommand {
 public:
  explicit KeyboardCommand(KeyboardConfig config);

  KeyboardActions onKey(const KeyPress& key, double now_s);
  /// One stop when the key timeout elapsed while moving.
  KeyboardActions onTimer(double now_s);

  double gain() const { return gain_; }
  const VelocityCommand& current() const { return current_; }
  bool moving() const { return !current_.isZero(); }

 private:
  KeyboardConfig config_;
  double gain_;
  VelocityCommand current_;
  double last_motion_s_ = 0.0;
};

/// The help screen listing every key, with the current speeds.
std::string keyboardHelp(const KeyboardConfig& config, double gain);

}  // namespace thorvald_teleop
