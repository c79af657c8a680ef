// Node `keyboard_teleop`: drive from a terminal (see README.md and the help screen it prints).
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include <geometry_msgs/Twist.h>
#include <ros/ros.h>
#include <thorvald_common/ros/param_reader.h>

#include "thorvald_teleop/key_decoder.h"
#include "thorvald_teleop/keyboard_command.h"
#include "thorvald_common/stop_signals.h"

namespace thorvald_teleop {
namespace {

using thorvald_common::StopSignals;

/// Puts a terminal in raw mode (no echo, no line buffering, Ctrl-C as a byte) and restores it on destruction.
class RawTerminal {
 public:
  explicit RawTerminal(int fd) : fd_(fd) {
    if (!isatty(fd_) || tcgetattr(fd_, &saved_) != 0) return;
    termios raw = saved_;
    raw.c_lflag &= static_cast<tcflag_t>(~(ICANON | ECHO | ISIG));
    raw.c_iflag &= static_cast<tcflag_t>(~(IXON | ICRNL));
    raw.c_cc[VMIN] = 0;
    raw.c_cc[VTIME] = 0;
    active_ = tcsetattr(fd_, TCSANOW, &raw) == 0;
  }
  ~RawTerminal() {
    if (active_) tcsetattr(fd_, TCSANOW, &saved_);
  }
  RawTerminal(const RawTerminal&) = delete;
  RawTerminal& operator=(const RawTerminal&) = delete;
  bool active() const { return active_; }

 private:
  int fd_;
  termios saved_{};
  bool active_ = false;
};

geometry_msgs::Twist toTwist(const VelocityCommand& c) {
  geometry_msgs::Twist t;
  t.linear.x = c.linear_x;
  t.linear.y = c.linear_y;
  t.angular.z = c.angular_z;
  return t;
}

struct KeyboardParams {
  KeyboardConfig config;
  double repeat_rate_hz = 10.0;  ///< [Hz] a held (latched) command is republished at this rate
};

KeyboardParams loadParams(ros::NodeHandle& pnh) {
  using thorvald_common::ParamRange;
  thorvald_common::ParamReader params(pnh);
  KeyboardParams p;
  KeyboardConfig& c = p.config;
  c.linear_speed_max = params.number("linear_speed_max", c.linear_speed_max, ParamRange::aboveUpTo(0.0, 10.0), "m/s");
  c.angular_speed_max =
      params.number("angular_speed_max", c.angular_speed_max, ParamRange::aboveUpTo(0.0, 10.0), "rad/s");
  c.gain = params.number("gain", c.gain, ParamRange::above(0.0));
  c.gain_step = params.number("gain_step", c.gain_step, ParamRange::above(0.0));
  c.gain_min = params.number("gain_min", c.gain_min, ParamRange::above(0.0));
  c.gain_max = params.number("gain_max", c.gain_max, ParamRange::above(0.0));
  c.key_timeout_s = params.number("key_timeout", c.key_timeout_s, ParamRange::closed(0.0, 60.0), "s, 0 = off");
  p.repeat_rate_hz = params.number("repeat_rate", p.repeat_rate_hz, ParamRange::aboveUpTo(0.0, 1000.0), "Hz");
  const std::string error = validateKeyboardConfig(c);
  if (!error.empty()) throw thorvald_common::ParamError(params.node() + ": ~" + error);
  params.finish();
  return p;
}

void print(const std::string& text) {
  std::fputs(text.c_str(), stdout);
  std::fflush(stdout);
}

bool stopping() { return StopSignals::requested() || !ros::ok(); }

int run(ros::NodeHandle& nh, ros::NodeHandle& pnh, StopSignals& stop_signals) {
  if (stopping()) return 0;  // stopped while roscpp was still waiting for the master: nothing was published
  // From here on the loop watches the signal flag and publishes a final stop while roscpp still runs.
  stop_signals.setOnSignal(nullptr);
  const KeyboardParams params = loadParams(pnh);
  const KeyboardConfig& config = params.config;
  const double repeat_rate_hz = params.repeat_rate_hz;
  ros::Publisher pub = nh.advertise<geometry_msgs::Twist>("cmd_vel", 1);
  KeyboardCommand command(config);
  KeyDecoder decoder;
  RawTerminal terminal(STDIN_FILENO);
  if (!terminal.active()) ROS_WARN("keyboard_teleop: stdin is not a terminal; reading keys from it anyway");
  print(keyboardHelp(config, command.gain()));

  ros::WallTime last_publish;
  auto publish = [&](const VelocityCommand& c) {
    pub.publish(toTwist(c));
    last_publish = ros::WallTime::now();
  };
  bool quit = false;
  while (!quit && !stopping()) {
    pollfd pfd{STDIN_FILENO, POLLIN, 0};
    if (poll(&pfd, 1, 20) > 0) {  // 20 ms: resolution of the key timeout and the repeat
      char buffer[64];
      const ssize_t n = read(STDIN_FILENO, buffer, sizeof(buffer));
      if (n <= 0) {
        ROS_WARN("keyboard_teleop: end of input on stdin, stopping (run it in a terminal)");
        quit = true;  // end of input: stop as on Ctrl-D
      } else {
        for (const KeyPress& key : decoder.feed(std::string(buffer, static_cast<std::size_t>(n)))) {
          const KeyboardActions a = command.onKey(key, ros::WallTime::now().toSec());
          if (a.command) publish(*a.command);
          if (a.show_help) print(keyboardHelp(config, command.gain()));
          if (a.gain_changed) {
            char line[96];
            std::snprintf(line, sizeof(line), "speed: %.2f m/s, %.2f rad/s\r\n",
                          config.linear_speed_max * command.gain(), config.angular_speed_max * command.gain());
            print(line);
          }
          quit = quit || a.quit;
        }
      }
    }
    const KeyboardActions timed = command.onTimer(ros::WallTime::now().toSec());
    if (timed.command) publish(*timed.command);
    if (command.moving() && ros::WallTime::now() - last_publish >= ros::WallDuration(1.0 / repeat_rate_hz)) {
      publish(command.current());  // keeps the mux input alive while a latched command is held
    }
    ros::spinOnce();
  }
  publish(VelocityCommand());
  print("stopped\r\n");
  // The publisher writes on roscpp's network thread: give the final stop time to leave before exiting.
  ros::WallDuration(0.3).sleep();
  return 0;
}

}  // namespace
}  // namespace thorvald_teleop

int main(int argc, char** argv) {
  ros::init(argc, argv, "keyboard_teleop", ros::init_options::NoSigintHandler);
  // SIGINT and SIGTERM end any wait for the master, then the key loop (with a final stop); destroyed last.
  thorvald_common::StopSignals stop_signals(ros::requestShutdown, 0.7);
  // Waits for the master until it answers or a signal arrives; outlives the try block: the last handle's
  // destruction shuts logging down.
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    return thorvald_teleop::run(nh, pnh, stop_signals);
  } catch (const std::exception& e) {
    ROS_FATAL("keyboard_teleop cannot start: %s", e.what());
    return 1;
  }
}
