#include "thorvald_teleop/keyboard_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace thorvald_teleop {
namespace {

// Direction of a motion key: forward, left, yaw (each -1, 0 or 1).
struct Motion {
  double forward, left, yaw;
};

std::optional<Motion> motionOf(const KeyPress& key) {
  switch (key.kind) {
    case KeyPress::Kind::kUp:
      return Motion{1, 0, 0};
    case KeyPress::Kind::kDown:
      return Motion{-1, 0, 0};
    case KeyPress::Kind::kLeft:
      return Motion{0, 0, 1};
    case KeyPress::Kind::kRight:
      return Motion{0, 0, -1};
    case KeyPress::Kind::kCharacter:
      break;
  }
  switch (key.character) {
    case 'w':
      return Motion{1, 0, 0};
    case 's':
      return Motion{-1, 0, 0};
    case 'a':
      return Motion{0, 0, 1};
    case 'd':
      return Motion{0, 0, -1};
    case 'q':
      return Motion{0, 1, 0};
    case 'e':
      return Motion{0, -1, 0};
    default:
      return std::nullopt;
  }
}

}  // namespace

std::string validateKeyboardConfig(const KeyboardConfig& c) {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(c.linear_speed_max)) return "linear_speed_max must be > 0 [m/s]";
  if (!positive(c.angular_speed_max)) return "angular_speed_max must be > 0 [rad/s]";
  if (!positive(c.gain_min) || !(c.gain_max >= c.gain_min)) return "gain_min must be > 0 and gain_max >= gain_min";
  if (!(c.gain >= c.gain_min && c.gain <= c.gain_max)) return "gain must be within [gain_min, gain_max]";
  if (!positive(c.gain_step)) return "gain_step must be > 0";
  if (!(std::isfinite(c.key_timeout_s) && c.key_timeout_s >= 0.0)) return "key_timeout must be >= 0 [s] (0 = off)";
  return {};
}

KeyboardCommand::KeyboardCommand(KeyboardConfig config) : config_(config), gain_(config.gain) {}

KeyboardActions KeyboardCommand::onKey(const KeyPress& key, double now_s) {
  KeyboardActions actions;
  if (const auto motion = motionOf(key)) {
    current_ = VelocityCommand();
    current_.linear_x = motion->forward * config_.linear_speed_max * gain_;
    current_.linear_y = motion->left * config_.linear_speed_max * gain_;
    current_.angular_z = motion->yaw * config_.angular_speed_max * gain_;
    last_motion_s_ = now_s;
    actions.command = current_;
    return actions;
  }
  if (key.kind != KeyPress::Kind::kCharacter) return actions;
  const auto snap = [&](double v) {
    return config_.gain_min + std::round((v - config_.gain_min) / config_.gain_step) * config_.gain_step;
  };
  switch (key.character) {
    case ' ':
    case 'x':
      current_ = VelocityCommand();
      actions.command = current_;
      break;
    case '+':
    case '=':
    case '-': {
      const double step = key.character == '-' ? -config_.gain_step : config_.gain_step;
      const double next = std::clamp(snap(gain_ + step), config_.gain_min, config_.gain_max);
      actions.gain_changed = next != gain_;
      if (moving() && gain_ > 0.0) {
        current_ = current_.scaled(next / gain_);
        actions.command = current_;
        last_motion_s_ = now_s;
      }
      gain_ = next;
      break;
    }
    case 'h':
    case '?':
      actions.show_help = true;
      break;
    case 0x03:  // Ctrl-C
    case 0x04:  // Ctrl-D
      current_ = VelocityCommand();
      actions.command = current_;
      actions.quit = true;
      break;
    default:
      break;
  }
  return actions;
}

KeyboardActions KeyboardCommand::onTimer(double now_s) {
  KeyboardActions actions;
  if (config_.key_timeout_s > 0.0 && moving() && now_s - last_motion_s_ > config_.key_timeout_s) {
    current_ = VelocityCommand();
    actions.command = current_;
  }
  return actions;
}

std::string keyboardHelp(const KeyboardConfig& config, double gain) {
  char speeds[160];
  std::snprintf(speeds, sizeof(speeds), "speed: %.2f m/s, %.2f rad/s (gain %.2f of %.2f m/s, %.2f rad/s)\r\n",
                config.linear_speed_max * gain, config.angular_speed_max * gain, gain, config.linear_speed_max,
                config.angular_speed_max);
  std::string help =
      "Thorvald keyboard teleop\r\n"
      "------------------------\r\n"
      "  w / Up     forward          s / Down   backward\r\n"
      "  a / Left   turn left        d / Right  turn right\r\n"
      "  q          crab left        e          crab right\r\n"
      "  space / x  stop\r\n"
      "  + / -      speed up / down\r\n"
      "  h / ?      this help        Ctrl-C     stop and quit\r\n";
  if (config.key_timeout_s > 0.0) {
    char line[96];
    std::snprintf(line, sizeof(line), "Hold a key to keep moving: the robot stops %.1f s after the last key.\r\n",
                  config.key_timeout_s);
    help += line;
  } else {
    help += "A key keeps its motion until space.\r\n";
  }
  return help + speeds;
}

}  // namespace thorvald_teleop
